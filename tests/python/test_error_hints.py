"""Errors that tell the user what to write: the nearest known name for a mistyped type or key, our
name for a Mitsuba 3 one, and the expected and actual shapes of a numpy array."""
from __future__ import annotations

import copy

import numpy as np
import pytest

import pellucid


def _error(d: dict) -> str:
    with pytest.raises(pellucid.Error) as e:
        pellucid.load_dict(d)
    return str(e.value)


def test_mitsuba_material_names_get_ours(tiny_scene_dict) -> None:
    for mitsuba, ours in (("diffuse", "lambertian"), ("roughconductor", "rough_conductor"),
                          ("roughdiffuse", "oren_nayar"), ("thindielectric", "thin_dielectric")):
        d = copy.deepcopy(tiny_scene_dict)
        d["materials"]["white"] = {"type": mitsuba}
        assert f"materials.white.type: unknown material type '{mitsuba}' (Mitsuba's '{mitsuba}' is '{ours}' here; known: " \
            in _error(d)


def test_misspelled_types_and_keys_get_the_nearest_name(tiny_scene_dict) -> None:
    d = copy.deepcopy(tiny_scene_dict)
    d["materials"]["white"]["reflectanse"] = d["materials"]["white"].pop("reflectance", 0.5)
    assert _error(d).endswith("materials.white.reflectanse: unknown parameter (did you mean 'reflectance'?)")
    d = copy.deepcopy(tiny_scene_dict)
    d["materials"]["white"]["type"] = "lambertain"
    assert "unknown material type 'lambertain' (did you mean 'lambertian'? known: " in _error(d)
    d = copy.deepcopy(tiny_scene_dict)
    d["shapes"][0]["type"] = "rectangel"
    assert "shapes[0].type: unknown shape type 'rectangel' (did you mean 'rectangle'? known: " in _error(d)
    # Nothing close: no suggestion, just the list.
    d["shapes"][0]["type"] = "teapot"
    assert "unknown shape type 'teapot' (known: " in _error(d)


def test_mitsuba_keys_get_ours() -> None:
    with pytest.raises(pellucid.Error, match=r"spec_trans: unknown parameter \(Mitsuba's 'spec_trans' is "
                                             r"'specular_transmission' here\)"):
        pellucid.bsdf({"type": "principled", "variant": "2015", "spec_trans": 0.5})


def test_bsdf_arrays_of_the_wrong_shape_state_both_shapes() -> None:
    b = pellucid.bsdf({"type": "lambertian"})
    with pytest.raises(pellucid.Error, match=r"wo: expected an array of shape \(N, 3\), got shape \(4, 2\)"):
        b.eval(np.zeros((4, 2), np.float32), np.zeros((4, 3), np.float32))
    with pytest.raises(pellucid.Error, match=r"wo and wi: expected the same number of rows, got shapes \(4, 3\) and "
                                             r"\(5, 3\)"):
        b.pdf(np.zeros((4, 3), np.float32), np.zeros((5, 3), np.float32))


def test_images_of_the_wrong_shape_state_both_shapes(tmp_path) -> None:
    path = tmp_path / "x.exr"
    # Any channel count is an image (EXR holds them all); other ranks and empty sides are not.
    for shape, text in (((4, 0, 3), r"\(4, 0, 3\)"), ((4,), r"\(4,\)"), ((2, 2, 2, 3), r"\(2, 2, 2, 3\)")):
        with pytest.raises(pellucid.Error, match=r"x\.exr: image array: expected shape \(H, W\) or \(H, W, C\) "
                                                 r"with H, W, C >= 1, got " + text):
            pellucid.write_image(str(path), np.zeros(shape, np.float32))
    assert not path.exists()

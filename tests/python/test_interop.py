"""Mitsuba 3 XML scenes and mesh files load through the same IR as JSON."""
from __future__ import annotations

import numpy as np
import pytest

import pellucid


def test_mitsuba_xml_scene_renders(root) -> None:
    scene = pellucid.load_file(root / "tests" / "data" / "mitsuba" / "spheres.xml")
    img = pellucid.render(scene, spp=2)
    assert img.ndim == 3 and np.isfinite(img).all() and img.mean() > 0


def test_bad_xml_names_file_and_line(tmp_path) -> None:
    bad = tmp_path / "bad.xml"
    bad.write_text('<scene version="3.0.0">\n  <shape type="sphere">\n    <bsdf type="hair"/>\n  </shape>\n</scene>\n')
    with pytest.raises(pellucid.Error, match=r"bad\.xml:3: unsupported bsdf plugin 'hair'"):
        pellucid.load_file(bad)


def test_obj_mesh_and_missing_file(tmp_path) -> None:
    (tmp_path / "q.obj").write_text("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n")
    d = {"camera": {"type": "perspective", "fov": 40,
                    "to_world": [{"look_at": {"origin": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
         "film": {"width": 16, "height": 16},
         "shapes": [{"type": "obj", "filename": "q.obj"}],
         "lights": [{"type": "constant", "radiance": 1.0}]}
    img = pellucid.render(pellucid.load_dict(d, base_dir=tmp_path), spp=2)
    assert img[8, 8].mean() > 0.1
    d["shapes"][0] = {"type": "ply", "filename": "missing.ply"}
    with pytest.raises(pellucid.Error, match=r"shapes\[0\]\.filename: .*missing\.ply"):
        pellucid.load_dict(d, base_dir=tmp_path)


def test_obj_usemtl_materials_from_a_dict(tmp_path) -> None:
    """Per-face OBJ materials through the Python dict path: usemtl names map to scene materials,
    the shape's `materials` renames them, an unknown name without a shape material is an error."""
    (tmp_path / "two.obj").write_text("v -1 -1 0\nv 0 -1 0\nv 0 1 0\nv -1 1 0\nv 1 -1 0\nv 1 1 0\n"
                                      "usemtl left\nf 1 2 3 4\nusemtl right\nf 2 5 6 3\n")
    d = {"camera": {"type": "perspective", "fov": 30,
                    "to_world": [{"look_at": {"origin": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
         "film": {"width": 8, "height": 4, "filter": {"type": "box", "radius": 0.001}},
         "integrator": {"type": "aov", "aov": "albedo"},
         "materials": {"left": {"type": "lambertian", "reflectance": [0.8, 0.1, 0.1]},
                       "blue": {"type": "lambertian", "reflectance": [0.1, 0.1, 0.8]}},
         "shapes": [{"type": "obj", "filename": "two.obj", "materials": {"right": "blue"}}]}
    img = np.array(pellucid.render(pellucid.load_dict(d, base_dir=tmp_path), spp=2))
    np.testing.assert_allclose(img[:, :4], np.broadcast_to([0.8, 0.1, 0.1], img[:, :4].shape), atol=1e-5)
    np.testing.assert_allclose(img[:, 4:], np.broadcast_to([0.1, 0.1, 0.8], img[:, 4:].shape), atol=1e-5)
    del d["shapes"][0]["materials"]
    with pytest.raises(pellucid.Error, match=r"shapes\[0\]: mesh 'two\.obj' face material 'right' is not a scene material"):
        pellucid.load_dict(d, base_dir=tmp_path)

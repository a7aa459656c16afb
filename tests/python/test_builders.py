"""pellucid.scenes and pellucid.materials: dict builders that match the files and the registry."""
from __future__ import annotations

import inspect
import json

import numpy as np
import pytest

import pellucid
from pellucid import materials, scenes

from conftest import ROOT


def test_cornell_box_is_the_json_scene_and_renders_identically() -> None:
    path = ROOT / "scenes" / "cornell_box.json"
    assert scenes.cornell_box() == json.loads(path.read_text())
    small = {"film": {"width": 40, "height": 40}}
    a = pellucid.render(pellucid.load_dict(scenes.cornell_box(**small)), spp=4, seed=11)
    d = json.loads(path.read_text())
    d["film"].update(width=40, height=40)
    b = pellucid.render(pellucid.load_dict(d), spp=4, seed=11)
    assert np.array_equal(a, b) and a.mean() > 0.05
    # And the full-size dict against load_file, at a low spp.
    full_a = pellucid.render(pellucid.load_dict(scenes.cornell_box()), spp=1, seed=5)
    full_b = pellucid.render(pellucid.load_file(path), spp=1, seed=5)
    assert np.array_equal(full_a, full_b)


def test_overrides_merge_without_touching_the_defaults() -> None:
    d = scenes.cornell_box(film={"width": 64}, integrator={"max_depth": 3}, sampler=None)
    assert d["film"] == {"width": 64, "height": 256, "filter": {"type": "gaussian", "stddev": 0.5},
                         "reconstruction": "splatting"}
    assert d["integrator"] == {"type": "path", "max_depth": 3, "rr_depth": 5}
    assert "sampler" not in d
    assert scenes.cornell_box()["film"]["width"] == 256  # fresh dict each call


def test_furnace_renders_the_environment_radiance() -> None:
    """White furnace: a white Lambertian sphere (albedo 1) under radiance 1 is 1 at every pixel in
    expectation. Under mis (the default) the environment is BSDF sampling's alone and every path is 1
    up to float rounding; under nee, a z-test of the image mean against 1 with the renderer's own
    variance estimate, |z| < 4 (two-sided significance 6e-5); fixed seeds."""
    image = pellucid.render(pellucid.load_dict(scenes.furnace(width=24, height=24)), spp=32, seed=2)
    assert np.abs(image - 1.0).max() < 1e-5
    d = scenes.furnace(width=24, height=24)
    d["integrator"]["strategy"] = "nee"
    image, variance, _ = pellucid.render_with_stats(pellucid.load_dict(d), spp=32, seed=2)
    n = image.size
    mean = float(np.mean(image, dtype=np.float64))
    se = float(np.sqrt(np.sum(variance, dtype=np.float64)) / n)
    assert se > 0
    assert abs(mean - 1.0) / se < 4, (mean, se)
    # An absorbing material is darker: the test can fail.
    grey, _, _ = pellucid.render_with_stats(
        pellucid.load_dict(scenes.furnace(materials.lambertian(0.5), width=8, height=8)), spp=8, seed=2)
    assert grey.mean() < 0.9


def test_material_ball_builds_every_material_type() -> None:
    for name in pellucid._core.registry_types()["materials"]:
        builder = getattr(materials, name)
        scene = pellucid.load_dict(scenes.material_ball(builder(), width=16, height=12, spp=1))
        img = pellucid.render(scene)
        assert img.shape == (12, 16, 3) and np.isfinite(img).all() and img.mean() > 0.01, name
    assert scenes.material_ball("dielectric")["materials"]["ball"] == {"type": "dielectric"}
    with pytest.raises(TypeError, match="material"):
        scenes.material_ball(3)


def _builder_keys(type_name: str, d: dict) -> set:
    recs = pellucid._core.record_parameters({"materials": {"m": d}})
    return {k for path, t, keys in recs if path == "materials.m" for k in keys} - {"type"}


def test_every_registered_material_has_a_builder_with_the_json_keys() -> None:
    names = pellucid._core.registry_types()["materials"]
    assert sorted(names) == sorted(materials.__all__)
    for name in names:
        fn = getattr(materials, name)
        params = list(inspect.signature(fn).parameters)
        assert fn() == {"type": name}
        # The keywords are exactly the keys the C++ builder looks up for this type (its Properties
        # record), so a renamed or added parameter fails here.
        looked_up = _builder_keys(name, {"type": name})
        if name == "conductor" or name == "rough_conductor":  # eta/k are an alternative to material
            looked_up |= _builder_keys(name, {"type": name, "eta": 1.5, "k": 1.0})
        if name == "oren_nayar":  # sigma is read by the classic variant
            looked_up |= _builder_keys(name, {"type": name, "variant": "classic"})
        if name == "subsurface":  # the boundary's microfacet keys are read when it is rough
            looked_up |= _builder_keys(name, {"type": name, "alpha": 0.1})
        if name in ("rough_conductor", "rough_dielectric", "rough_plastic"):
            looked_up |= _builder_keys(name, {"type": name, "alpha_u": 0.1, "alpha_v": 0.2})
            looked_up |= _builder_keys(name, {"type": name, "roughness": 0.3})
        assert set(params) == looked_up, (name, set(params) ^ looked_up)
        assert "docs/scene-format.md" in (fn.__doc__ or ""), name
        # Every keyword produces its key, and the result builds.
        d = fn(**{p: None for p in params})
        assert d == {"type": name}


def test_material_builders_produce_valid_materials() -> None:
    cases = [
        materials.lambertian(0.8),
        materials.oren_nayar([0.5, 0.4, 0.3], variant="classic", sigma=20),
        materials.conductor("Au"),
        materials.conductor(eta=[0.2, 0.4, 1.4], k=[3.9, 2.4, 1.6]),
        materials.rough_conductor("Cu", roughness=0.4, multiple_scattering=True),
        materials.dielectric(1.5),
        materials.rough_dielectric("bk7", alpha=0.2),
        materials.thin_dielectric(1.33),
        materials.plastic([0.1, 0.2, 0.6], int_ior=1.5),
        materials.rough_plastic(0.5, alpha_u=0.1, alpha_v=0.3),
        materials.principled([0.9, 0.4, 0.1], metallic=0.5, clearcoat=1.0),
        materials.subsurface([0.9, 0.6, 0.4], mfp=0.01, model="dipole", int_ior=1.4),
    ]
    assert cases[0] == {"type": "lambertian", "reflectance": 0.8}
    assert cases[4] == {"type": "rough_conductor", "material": "Cu", "roughness": 0.4, "multiple_scattering": True}
    for c in cases:
        b = pellucid.bsdf(c)
        albedo = b.albedo([[0.0, 0.6, 0.8]], 256)
        assert np.isfinite(albedo).all() and (albedo > 0).all(), c
    with pytest.raises(TypeError):
        materials.lambertian(0.5, 0.2)  # only the first parameter is positional
    with pytest.raises(pellucid.Error, match="alpha: value -1 must be >= 0"):
        pellucid.bsdf(materials.rough_conductor("Au", alpha=-1))


def test_objects_print_themselves(tiny_scene_path) -> None:
    scene = pellucid.load_file(tiny_scene_path)
    assert "Scene" in repr(scene) and "32" in repr(scene)
    b = pellucid.bsdf(materials.rough_conductor("Au", alpha=0.2))
    r = repr(b)
    assert r and "object at 0x" not in r
    img = pellucid.render(scene, spp=1)
    assert repr(img).startswith("Image(32x24, 3 channels")
    assert repr(pellucid._core.RenderProgress()).startswith("RenderProgress(")


def test_readme_python_example_runs(tmp_path, monkeypatch, capsys) -> None:
    """The README's Python quick start runs as written (with spp capped at 2 to keep it fast)."""
    import re

    text = (ROOT / "README.md").read_text()
    snippet = re.search(r"## Python\n\n```python\n(.*?)```", text, re.S).group(1)
    assert len([ln for ln in snippet.splitlines() if ln.strip()]) <= 10
    real = pellucid.render
    monkeypatch.setattr(pellucid, "render", lambda scene, spp=None, **k: real(scene, spp=min(spp or 2, 2), **k))
    monkeypatch.chdir(tmp_path)
    (tmp_path / "out").mkdir()
    exec(compile(snippet, "README.md", "exec"), {})
    out = capsys.readouterr().out
    assert out.startswith("Image(128x128, 3 channels, float32") and "Comparison(rmse=" in out
    assert pellucid.read_image(tmp_path / "out" / "box.png").shape == (128, 128, 3)

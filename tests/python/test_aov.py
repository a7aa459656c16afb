"""pellucid.aov.render_aov and `pellucid-render --aov`: AOVs from a Scene, a path or a dict."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import pellucid
from pellucid.aov import AOVS, render_aov

from conftest import ROOT

CLI = ROOT / "build" / "py" / "cpp" / "pellucid-render"


def _sphere_scene(aov_integrator: bool = False) -> dict:
    d = {
        "camera": {"type": "perspective", "fov": 40,
                   "to_world": [{"look_at": {"origin": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "film": {"width": 16, "height": 12, "filter": {"type": "box", "radius": 0.001}},
        "sampler": {"sample_count": 2},
        "shapes": [{"type": "sphere", "radius": 1.0,
                    "material": {"type": "lambertian", "reflectance": [0.2, 0.4, 0.6]}}],
    }
    if aov_integrator:
        d["integrator"] = {"type": "aov", "aov": "normal"}
    return d


def test_render_aov_inputs_agree(tmp_path) -> None:
    d = _sphere_scene()
    path = tmp_path / "s.json"
    import json

    path.write_text(json.dumps(d))
    a = render_aov(d, "normal", seed=3)
    b = render_aov(str(path), "normal", seed=3)
    c = render_aov(pellucid.load_dict(d), "normal", seed=3)
    e = pellucid.render(pellucid.load_dict(_sphere_scene(True)), seed=3)
    assert a.shape == (12, 16, 3) and a.dtype == np.float32
    assert np.array_equal(a, b) and np.array_equal(a, c) and np.array_equal(a, e)


def test_render_aov_values() -> None:
    d = _sphere_scene()
    n = render_aov(d, "normal")
    hit = np.abs(n).sum(axis=2) > 0
    assert hit.sum() > 20 and (~hit).sum() > 20
    # Unit normals, signed (left half of the sphere points to −x), facing the camera (+z).
    assert np.allclose(np.linalg.norm(n[hit], axis=1), 1.0, atol=1e-3)
    assert n[hit][:, 0].min() < -0.5 and n[hit][:, 0].max() > 0.5
    assert (n[hit][:, 2] > 0).all()
    depth = render_aov(d, "depth")
    assert (depth[~hit] == 0).all()
    assert depth[hit].min() >= 3.0 - 1e-4 and depth[hit].max() < 4.0
    albedo = render_aov(d, "albedo", spp=4)
    assert np.allclose(albedo[hit], [0.2, 0.4, 0.6], atol=1e-6)  # cosine sampling: weight = ρ exactly
    assert set(AOVS) == {"albedo", "normal", "depth"}


def test_render_aov_bad_input() -> None:
    d = _sphere_scene()
    with pytest.raises(pellucid.Error, match="aov: unknown aov 'nromal'"):
        render_aov(d, "nromal")
    with pytest.raises(pellucid.Error, match="spp"):
        render_aov(d, "depth", spp=0)
    with pytest.raises(pellucid.Error, match="scene: expected"):
        render_aov(42, "depth")  # type: ignore[arg-type]
    with pytest.raises(pellucid.Error, match="integrator.aov: unknown aov"):
        pellucid.load_dict({"integrator": {"type": "aov", "aov": "uv"}})


@pytest.mark.skipif(not CLI.exists(), reason="pellucid-render is built by `make`")
def test_cli_aov_flag(tmp_path, tiny_scene_path) -> None:
    out = tmp_path / "depth.exr"
    r = subprocess.run([str(CLI), str(tiny_scene_path), "-o", str(out), "--aov", "depth", "--spp", "2", "-q"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    ref = render_aov(str(tiny_scene_path), "depth", spp=2)
    assert np.array_equal(pellucid.read_image(str(out)), ref)
    bad = subprocess.run([str(CLI), str(tiny_scene_path), "-o", str(out), "--aov", "uv"],
                         capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and "--aov: unknown aov 'uv'" in bad.stderr


def test_python_cli_aov_flag_matches_the_cpp_cli(tmp_path, tiny_scene_path) -> None:
    """`python -m pellucid render --aov` takes the same flag as pellucid-render and gives the same image."""
    assert pellucid.render_aov is render_aov and pellucid.AOVS == AOVS
    out = tmp_path / "normal.exr"
    r = subprocess.run([sys.executable, "-m", "pellucid", "render", str(tiny_scene_path), "-o", str(out),
                        "--aov", "normal", "--spp", "2", "--seed", "4", "-q"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert np.array_equal(pellucid.read_image(str(out)), render_aov(str(tiny_scene_path), "normal", spp=2, seed=4))
    bad = subprocess.run([sys.executable, "-m", "pellucid", "render", str(tiny_scene_path), "-o", str(out),
                          "--aov", "uv"], capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and "--aov" in bad.stderr

"""AOVs: pellucid.render(..., aovs=[...]) and RenderLayers, the multi-layer EXR (write_layers /
read_layers), `--aovs` in both command lines, and the one-AOV render_aov / `--aov`."""
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
    assert AOVS == ("albedo", "normal", "depth", "position", "uv", "shape_id", "material_id", "variance",
                    "sample_count")


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


# ---- render(..., aovs=...) ----------------------------------------------------------------------

def _plane_scene() -> dict:
    """A Lambertian (ρ = 0.3) rectangle [-1.5, 1.5]² in z = -0.5, seen from z = 2.5 (slightly off
    the axis, so no pixel-centre ray runs along the rectangle's diagonal), with a 0.001-pixel box
    filter: every pixel's samples lie within 0.001 px of its centre."""
    return {
        "camera": {"type": "perspective", "fov": 70,
                   "to_world": [{"look_at": {"origin": [0.0123, -0.0371, 2.5], "target": [0.0123, -0.0371, 0],
                                             "up": [0, 1, 0]}}]},
        "film": {"width": 20, "height": 16, "filter": {"type": "box", "radius": 0.001}},
        "sampler": {"sample_count": 3, "seed": 2},
        "shapes": [{"type": "rectangle", "to_world": [{"scale": 1.5}, {"translate": [0, 0, -0.5]}],
                    "material": {"type": "lambertian", "reflectance": 0.3}}],
    }


def test_render_with_aovs_returns_named_images() -> None:
    scene = pellucid.load_dict(_plane_scene())
    r = pellucid.render(scene, aovs=["albedo", "normal", "depth", "uv", "shape_id", "sample_count", "variance"])
    assert isinstance(r, pellucid.RenderLayers)
    assert list(r.aovs) == ["albedo", "normal", "depth", "uv", "shape_id", "sample_count", "variance"]
    assert isinstance(r.image, pellucid.Image) and r.image.shape == (16, 20, 3)
    assert all(isinstance(a, pellucid.Image) for a in r.aovs.values())
    assert {k: v.shape[2] for k, v in r.aovs.items()} == {"albedo": 3, "normal": 3, "depth": 1, "uv": 2,
                                                         "shape_id": 1, "sample_count": 1, "variance": 3}
    # The beauty is the plain render's image, bit for bit; variance is its film's.
    img, var, _ = pellucid.render_with_stats(scene)
    assert np.array_equal(r.image, img) and np.array_equal(r["variance"], var)
    hit = r["shape_id"][:, :, 0] == 0
    assert 50 < hit.sum() < hit.size - 20
    assert np.allclose(r["albedo"][hit], 0.3, atol=1e-6)          # cosine sampling: weight = ρ exactly
    assert np.allclose(r["normal"][hit], [0, 0, 1], atol=1e-6)
    assert (r["albedo"][~hit] == 0).all() and (r["shape_id"][~hit] == -1).all()
    # Depth of a plane at distance 3 along the axis: 3 / cos(angle of the pixel-centre ray).
    d = r["depth"][hit][:, 0]
    assert d.min() > 3.0 - 1e-4 and d.max() < 3.0 / np.cos(np.radians(55))
    assert (r["sample_count"] == 3).all()
    assert r.stats["spp"] == 3 and r.stats["aov_seconds"] > 0 and r.stats["shape_names"] == ["shapes[0]"]
    # A comma-separated string works too; unknown names are errors naming the known ones.
    assert list(pellucid.render(scene, aovs="depth, albedo").aovs) == ["depth", "albedo"]
    with pytest.raises(pellucid.Error, match=r"aovs: unknown aov 'nromal' \(known: albedo, normal, depth"):
        pellucid.render(scene, aovs=["nromal"])
    with pytest.raises(KeyError, match="no AOV 'uv'"):
        pellucid.render(scene, aovs=["depth"])["uv"]


def test_layers_round_trip_through_one_multilayer_exr(tmp_path) -> None:
    scene = pellucid.load_dict(_plane_scene())
    r = pellucid.render(scene, aovs=list(AOVS))
    path = tmp_path / "sub" / "frame.exr"
    r.save(path)
    back = pellucid.read_layers(path)
    assert list(back.aovs) == list(AOVS)
    assert np.array_equal(back.image, r.image)
    for name in AOVS:
        assert np.array_equal(back[name], r[name]), name
    assert back.stats["pellucid:spp"] == 3
    # The channel names a compositor sees, and every channel through read_image.
    names = pellucid.read_image_attributes(path)["pellucid:channels"].split(",")
    assert names[:7] == ["R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "normal.X"]
    assert "depth.Z" in names and "uv.U" in names and "uv.V" in names and "shape_id.X" in names
    assert pellucid.read_image(path).shape == (16, 20, 3 + 3 + 3 + 1 + 3 + 2 + 1 + 1 + 3 + 1)
    # write_layers takes any named arrays; sizes must agree.
    pellucid.write_layers(tmp_path / "x.exr", None, {"mask": np.ones((2, 3)), "rgba": np.zeros((2, 3, 4))})
    with pytest.raises(pellucid.Error, match="no unnamed"):
        pellucid.read_layers(tmp_path / "x.exr")
    with pytest.raises(pellucid.Error, match=r"layer 'b' is 4x2, the first layer 3x2"):
        pellucid.write_layers(tmp_path / "y.exr", np.zeros((2, 3, 3)), {"b": np.zeros((2, 4, 3))})
    with pytest.raises(pellucid.Error, match="use a .exr path"):
        pellucid.write_layers(tmp_path / "y.png", np.zeros((2, 3, 3)), {"b": np.zeros((2, 3, 3))})


def test_read_and_write_image_keep_every_channel(tmp_path) -> None:
    seven = np.arange(2 * 3 * 7, dtype=np.float32).reshape(2, 3, 7) - 5.0
    pellucid.write_image(tmp_path / "seven.exr", seven)
    assert np.array_equal(pellucid.read_image(tmp_path / "seven.exr"), seven)
    rgba = np.array([[[1.0, 0.0, 0.0, 0.5], [0.0, 1.0, 0.0, 0.25]]], dtype=np.float32)
    pellucid.write_image(tmp_path / "rgba.png", rgba)
    back = pellucid.read_image(tmp_path / "rgba.png")
    assert back.shape == (1, 2, 4)
    assert np.allclose(back, np.round(rgba * 255) / 255, atol=1e-6)  # colour as written, alpha linear
    with pytest.raises(pellucid.Error, match="holds 1 to 4 channels, the image has 7"):
        pellucid.write_image(tmp_path / "seven.png", seven)


@pytest.mark.skipif(not CLI.exists(), reason="pellucid-render is built by `make`")
def test_both_clis_write_the_same_layers(tmp_path, tiny_scene_path) -> None:
    """`--aovs` in pellucid-render and python -m pellucid render: the same multi-layer EXR as
    render(..., aovs=...); a PNG output gets the beauty; without an .exr output it is an error."""
    ref = pellucid.render(pellucid.load_file(tiny_scene_path), spp=2, seed=3, aovs=["albedo", "depth", "shape_id"])
    for cmd in ([str(CLI)], [sys.executable, "-m", "pellucid", "render"]):
        out, png = tmp_path / "a.exr", tmp_path / "a.png"
        r = subprocess.run(cmd + [str(tiny_scene_path), "-o", str(out), "-o", str(png), "--spp", "2", "--seed", "3",
                                  "--aovs", "albedo,depth,shape_id", "-q"], capture_output=True, text=True, timeout=120)
        assert r.returncode == 0, r.stderr
        back = pellucid.read_layers(out)
        assert list(back.aovs) == ["albedo", "depth", "shape_id"]
        assert np.array_equal(back.image, ref.image)
        for name in ref:
            assert np.array_equal(back[name], ref[name]), (cmd[0], name)
        assert pellucid.read_image(png).shape == ref.image.shape
        bad = subprocess.run(cmd + [str(tiny_scene_path), "-o", str(png), "--aovs", "albedo"],
                             capture_output=True, text=True, timeout=120)
        assert bad.returncode == 1 and "--aovs: AOVs are written as layers of a multi-layer EXR" in bad.stderr
        bad = subprocess.run(cmd + [str(tiny_scene_path), "-o", str(out), "--aovs", "albedo,nromal"],
                             capture_output=True, text=True, timeout=120)
        assert bad.returncode == 2 and "--aovs: unknown aov 'nromal'" in bad.stderr, bad.stderr

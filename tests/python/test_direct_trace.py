"""Small scenes are traced without Embree (docs/scene-format.md, "integrator"): every ray against every
triangle and sphere. PELLUCID_TRACE=embree has Embree trace them instead. Sphere hits are the same bit
for bit either way, so a scene of spheres renders the same image; triangle hits agree to float
rounding, so a scene with triangles renders the same image but for the few paths that rounding sends
another way."""
from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import pellucid

ROOT = Path(__file__).resolve().parents[2]
CLI = ROOT / "build" / "py" / "cpp" / "pellucid-render"


def _render(tmp_path: Path, scene: str | Path, trace: str) -> np.ndarray:
    """The image of a suite scene (by name) or of a scene file, traced directly where the scene
    allows it (default) or by Embree."""
    env = {k: v for k, v in os.environ.items() if k != "PELLUCID_TRACE"}
    if trace == "embree":
        env["PELLUCID_TRACE"] = "embree"
    out = tmp_path / f"{trace}.exr"
    r = subprocess.run([str(CLI), str(ROOT / "bench" / "suite" / scene), "-o", str(out), "--spp", "2", "--threads", "1",
                        "-q"], capture_output=True, text=True, timeout=300, env=env)
    assert r.returncode == 0, r.stderr[-2000:]
    return np.asarray(pellucid.read_image(str(out)))


# A small rectangle far below everything, which no path reaches: a scene of spheres with it is traced
# directly (one of spheres alone goes to Embree).
FAR_RECTANGLE = {"type": "rectangle", "material": "clay",
                 "to_world": [{"scale": 0.01}, {"translate": [0, -1e5, 0]}]}


@pytest.mark.skipif(not CLI.exists(), reason="pellucid-render is built by `make`")
def test_spheres_render_the_same_image_either_way(tmp_path) -> None:
    # env_diffuse.json is one sphere alone.
    scene = json.loads((ROOT / "bench" / "suite" / "env_diffuse.json").read_text())
    scene["shapes"].append(FAR_RECTANGLE)
    path = tmp_path / "sphere.json"
    path.write_text(json.dumps(scene))
    a, b = _render(tmp_path, path, "default"), _render(tmp_path, path, "embree")
    assert np.array_equal(a, b)


@pytest.mark.skipif(not CLI.exists(), reason="pellucid-render is built by `make`")
def test_many_spheres_render_the_same_image_either_way(tmp_path) -> None:
    # 64 spheres in a grid (sorted into clusters that a float pre-test culls) under a constant
    # environment, seen from above at an angle: traced directly, the same image bit for bit.
    scene = json.loads((ROOT / "bench" / "suite" / "env_diffuse.json").read_text())
    scene["camera"]["to_world"] = [{"look_at": {"origin": [0, 5, 7], "target": [0, 0, 0], "up": [0, 1, 0]}}]
    scene["camera"]["fov"] = 50
    scene["film"]["width"] = scene["film"]["height"] = 128
    scene["shapes"] = [{"type": "sphere", "center": [0.8 * i - 2.8, 0.1 * (i % 3), 0.8 * j - 2.8],
                        "radius": 0.3 + 0.02 * ((i + j) % 4), "material": "clay"}
                       for i in range(8) for j in range(8)] + [FAR_RECTANGLE]
    path = tmp_path / "spheres.json"
    path.write_text(json.dumps(scene))
    a, b = _render(tmp_path, path, "default"), _render(tmp_path, path, "embree")
    assert np.isfinite(a).all() and a.mean() > 0.1
    assert np.array_equal(a, b)


@pytest.mark.skipif(not CLI.exists(), reason="pellucid-render is built by `make`")
def test_triangles_render_the_same_image_to_rounding(tmp_path) -> None:
    # glass.json: two rectangles (4 triangles) and two spheres, traced directly by default.
    a, b = _render(tmp_path, "glass.json", "default"), _render(tmp_path, "glass.json", "embree")
    assert a.shape == b.shape and np.isfinite(a).all()
    differs = np.abs(a - b) > 1e-3 * (np.abs(b) + 1e-2)
    # The switch is real: some path took the other triangle test's rounding another way ...
    assert differs.any()
    # ... but only a few: a pixel's paths are the same but where a hit differs by float rounding.
    assert differs.mean() < 0.02, differs.mean()

#!/usr/bin/env python3
"""Check the envmap light against Mitsuba 3: a diffuse sphere under a small asymmetric lat-long
map, rotated by to_world, rendered by both renderers from the same JSON; the background shows the
map directly, so any difference in orientation, texel placement or interpolation shows up there,
and the sphere checks the importance-sampled lighting.

    .venv/bin/python bench/envmap_check.py [--spp 256] [--mitsuba-python PATH]

The Mitsuba python defaults to $PELLUCID_MITSUBA_PYTHON, else bench/.venv-mitsuba/bin/python
(bench/peers/setup_mitsuba.sh). Exit status 0 when every pixel channel passes a two-sided z-test,
|a − b| / sqrt(var a + var b) < z at α = 0.01 Šidák-corrected over all pixel channels; 1 if not;
77 if Mitsuba is not available. tests/python/test_envmap_peer.py runs it (and skips without Mitsuba).
"""
from __future__ import annotations

import argparse
import json
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
RUNNER = ROOT / "bench" / "peers" / "mitsuba_runner.py"
SKIP = 77


def mitsuba_python(arg: str | None) -> pathlib.Path | None:
    for c in (arg, os.environ.get("PELLUCID_MITSUBA_PYTHON"), str(ROOT / "bench" / ".venv-mitsuba" / "bin" / "python")):
        if c and pathlib.Path(c).exists():
            return pathlib.Path(c)
    return None


def envmap_image(w: int = 32, h: int = 17) -> np.ndarray:
    """Lat-long map with a warm 'sun' spot, a blue-to-white sky gradient, a dark ground band, a
    green marker column and a texel checker: asymmetric under any flip or shift of u or v."""
    img = np.zeros((h, w, 3), np.float32)
    for y in range(h):
        for x in range(w):
            v = y / (h - 1)
            sky = np.array([0.3 + 0.5 * v, 0.4 + 0.4 * v, 1.0], np.float32) * (1.0 if v < 0.55 else 0.15)
            # A texel-by-texel checker: a half-texel shift or a flip changes every background pixel.
            img[y, x] = sky * (1.6 if (x + y) % 2 else 0.4)
    img[3, 5] = [40.0, 30.0, 10.0]
    img[4, 5] = [10.0, 8.0, 3.0]
    img[:, 20] += np.array([0.0, 1.5, 0.0], np.float32)
    return img


def scene_json(spp: int) -> dict:
    return {
        "camera": {"type": "perspective", "fov": 50,
                   "to_world": [{"look_at": {"origin": [0, 0.5, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "film": {"width": 48, "height": 36, "filter": {"type": "box"}},
        "sampler": {"sample_count": spp, "seed": 1},
        "integrator": {"type": "path", "max_depth": 4},
        "materials": {"m": {"type": "lambertian", "reflectance": [0.8, 0.6, 0.4]}},
        "shapes": [{"type": "sphere", "radius": 1.0, "material": "m"}],
        "lights": [{"type": "envmap", "filename": "sky.exr", "scale": 1.5,
                    "to_world": [{"rotate": {"axis": [0, 1, 0], "angle": 70}},
                                 {"rotate": {"axis": [1, 0, 0], "angle": 15}}]}],
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--passes", type=int, default=16, help="Mitsuba passes (for its per-pixel variance)")
    ap.add_argument("--mitsuba-python", default=None)
    ap.add_argument("--keep", default=None, help="directory to keep the scene and both images in")
    a = ap.parse_args(argv)
    mpy = mitsuba_python(a.mitsuba_python)
    if mpy is None:
        print("Mitsuba 3 not set up (bench/peers/setup_mitsuba.sh or PELLUCID_MITSUBA_PYTHON); skipped")
        return SKIP

    import pellucid
    from pellucid.bench import critical_z

    with tempfile.TemporaryDirectory() as tmp_s:
        tmp = pathlib.Path(a.keep or tmp_s)
        tmp.mkdir(parents=True, exist_ok=True)
        pellucid.write_image(tmp / "sky.exr", envmap_image())
        sj = scene_json(a.spp)
        (tmp / "scene.json").write_text(json.dumps(sj, indent=1))

        scene = pellucid.load_file(tmp / "scene.json")
        ours, ours_var, _ = pellucid.render_with_stats(scene, spp=a.spp, seed=1)
        pellucid.write_image(tmp / "pellucid.exr", ours)

        out = tmp / "mitsuba.exr"
        cmd = [str(mpy), str(RUNNER), str(tmp / "scene.json"), "--variant", "scalar_rgb", "--spp", str(a.spp),
               "--seed", "2", "--passes", str(a.passes), "--out", str(out), "--quiet"]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            print(r.stdout, r.stderr, sep="\n")
            return 1
        theirs = pellucid.read_image(out)
        theirs_var = pellucid.read_image(str(out)[:-4] + ".var.exr")

    n = ours.size
    z_max = critical_z(n, 0.01)
    z = np.abs(ours - theirs) / np.sqrt(ours_var + theirs_var + 1e-12)
    fails = int((z > z_max).sum())
    rel_mean = float(abs(ours.mean() - theirs.mean()) / theirs.mean())
    print(f"envmap vs Mitsuba 3 scalar_rgb, {ours.shape[1]}x{ours.shape[0]}, {a.spp} spp each:")
    print(f"  pixel channels beyond |z| > {z_max:.2f}: {fails} of {n}; max |z| = {float(z.max()):.2f}")
    print(f"  image means: pellucid {float(ours.mean()):.5f}, Mitsuba {float(theirs.mean()):.5f} "
          f"(relative difference {rel_mean:.2e})")
    return 0 if fails == 0 else 1


if __name__ == "__main__":
    sys.exit(main())

"""Mitsuba 3 references for tests/python/test_mitsuba_scenes.py (committed under ref/).

Run with the peer venv (bench/peers/setup_mitsuba.sh), from anywhere:

    bench/.venv-mitsuba/bin/python tests/data/mitsuba/make_refs.py [--passes 16] [--spp 256] [scene ...]

For each scene named (default: all of SCENES) it renders `passes` independent passes (seeds
0..passes-1) of `spp` samples per pixel with Mitsuba's llvm_ad_rgb variant (scalar_rgb when LLVM is
unavailable) and writes ref/<scene>.exr (the mean of the passes) and ref/<scene>.var.exr (the variance of that mean,
sample variance over passes / passes). Before rendering it writes the 8-bit PNGs that bumpmap.xml
reads (bump_height.png, bump_normals.png; deterministic, see make_bump_assets) where missing. The test imports `render_reference` from this file when
`mitsuba` is importable in the test's own interpreter, so the direct and committed paths agree.
"""
from __future__ import annotations

import argparse
import os
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
SCENES = ["aniso_sphere", "bumpmap", "cornell_mini", "cube_uv", "glass", "metals", "plastics", "principled", "spheres", "textures"]
PASSES, SPP = 16, 256

# Dr.Jit's LLVM backend needs a recent libLLVM (as bench/peers/mitsuba_runner.py).
for _p in ("/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1", "/usr/lib/x86_64-linux-gnu/libLLVM-19.so.1",
           "/usr/lib/llvm-19/lib/libLLVM.so.1"):
    if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(_p):
        os.environ["DRJIT_LIBLLVM_PATH"] = _p


def set_variant() -> str:
    import mitsuba as mi

    for v in ("llvm_ad_rgb", "scalar_rgb"):
        try:
            mi.set_variant(v)
            return v
        except Exception:  # noqa: BLE001 - variant not built or LLVM missing
            continue
    raise RuntimeError("no usable Mitsuba variant (need llvm_ad_rgb or scalar_rgb)")


def make_bump_assets() -> None:
    """bumpmap.xml's textures, written with Mitsuba's Bitmap (8-bit PNG) where missing.

    bump_height.png: 16x16 RGB heights whose channels differ (the bump gradient is that of the
    luminance, not of the channel mean). bump_normals.png: 16x16 tangent-space normals (OpenGL
    convention, encoded n/2 + 1/2) of sloped stripes, tilting up to about 35 degrees."""
    import numpy as np
    import mitsuba as mi

    y, x = np.mgrid[0:16, 0:16] + 0.5
    r = 0.5 + 0.35 * np.sin(2 * np.pi * x / 8) * np.cos(2 * np.pi * y / 16)
    g = 0.5 + 0.3 * np.cos(2 * np.pi * (x + y) / 16)
    b = 0.5 + 0.45 * np.sin(2 * np.pi * y / 4)
    height = np.clip(np.round(np.stack([r, g, b], -1) * 255), 0, 255).astype(np.uint8)
    n = np.stack([-0.7 * np.cos(2 * np.pi * x / 8), -0.35 * np.sin(2 * np.pi * y / 8), np.ones_like(x)], -1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    normals = np.clip(np.round((n * 0.5 + 0.5) * 255), 0, 255).astype(np.uint8)
    for name, data in (("bump_height.png", height), ("bump_normals.png", normals)):
        if not (HERE / name).exists():
            mi.Bitmap(data, mi.Bitmap.PixelFormat.RGB).write(str(HERE / name))


def render_reference(name: str, passes: int = PASSES, spp: int = SPP):
    """(mean, variance of the mean) as float32 (H, W, 3) arrays, from `passes` Mitsuba passes."""
    import numpy as np
    import mitsuba as mi

    if mi.variant() is None:
        set_variant()
    make_bump_assets()
    scene = mi.load_file(str(HERE / f"{name}.xml"), spp=spp)
    imgs = np.stack([np.array(mi.render(scene, seed=s, spp=spp))[..., :3] for s in range(passes)])
    return imgs.mean(axis=0).astype(np.float32), (imgs.var(axis=0, ddof=1) / passes).astype(np.float32)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--passes", type=int, default=PASSES)
    ap.add_argument("--spp", type=int, default=SPP)
    ap.add_argument("scenes", nargs="*", metavar="scene", help=f"scenes to render (default: {', '.join(SCENES)})")
    args = ap.parse_args()
    unknown = sorted(set(args.scenes) - set(SCENES))
    if unknown:
        ap.error(f"unknown scene(s) {', '.join(unknown)} (known: {', '.join(SCENES)})")
    import mitsuba as mi

    variant = set_variant()
    (HERE / "ref").mkdir(exist_ok=True)
    for name in args.scenes or SCENES:
        mean, var = render_reference(name, args.passes, args.spp)
        mi.Bitmap(mean).write(str(HERE / "ref" / f"{name}.exr"))
        mi.Bitmap(var).write(str(HERE / "ref" / f"{name}.var.exr"))
        print(f"{name}: {mean.shape[1]}x{mean.shape[0]}, {args.passes} x {args.spp} spp ({variant}), "
              f"mean {mean.mean():.4f}, mean rel. std {float((var ** 0.5 / (mean + 1e-6)).mean()):.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

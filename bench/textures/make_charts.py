"""Texture charts for issue 5: bump error against the finite-difference step, render time and error
with and without MIP maps, and aliasing (1-spp variance) with and without filtering.

    .venv/bin/python bench/textures/make_charts.py [--quick]

Writes CSV + PNG into bench/results/textures/. References are the same scene rendered at 8x the
resolution and box-downsampled (the true pixel average, up to noise). Timings are wall seconds on
this machine with the thread count given; compare them only within one run.
"""
from __future__ import annotations

import argparse
import copy
import csv
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
OUT = os.path.join(ROOT, "bench", "results", "textures")
TEX = os.path.join(ROOT, "bench", "cache", "textures")

import pellucid  # noqa: E402


def make_textures() -> None:
    os.makedirs(TEX, exist_ok=True)
    n = 512
    y, x = np.mgrid[0:n, 0:n] / n
    # Bricks with 2-texel mortar grooves: sharp height edges (worst case for steps and aliasing).
    row = np.floor(y * 16)
    xs = x * 8 + 0.5 * (row % 2)
    groove = ((xs % 1) < 4 / n * 8) | (((y * 16) % 1) < 4 / n * 16)
    h = np.where(groove, 0.0, 1.0).astype(np.float32)
    pellucid.write_image(os.path.join(TEX, "bricks_height.exr"), np.repeat(h[..., None], 3, 2))
    col = np.where(groove[..., None], [0.1, 0.1, 0.1], [0.7, 0.35, 0.2]).astype(np.float32)
    pellucid.write_image(os.path.join(TEX, "bricks.png"), col)


def plane_scene(material: dict, res=(96, 64), spp=64, seed=0, env=True) -> dict:
    # Without the environment light the only noise left is the pixel jitter over the texture: the
    # aliasing the study measures.
    lights = [{"type": "directional", "direction": [-1, -0.35, -0.2], "irradiance": 3.0}]
    if env:
        lights.append({"type": "constant", "radiance": 0.1})
    return {
        "film": {"width": res[0], "height": res[1], "filter": {"type": "box"}},
        "sampler": {"sample_count": spp, "seed": seed},
        "integrator": {"type": "path", "max_depth": 2, "strategy": "nee"},
        "camera": {"type": "perspective", "fov": 50,
                   "to_world": [{"look_at": {"origin": [0, 1.2, 3.5], "target": [0, 0, -3], "up": [0, 1, 0]}}]},
        "materials": {"m": material},
        "shapes": [{"type": "rectangle", "material": "m",
                    "to_world": [{"scale": 8}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}]}],
        "lights": lights,
    }


def render(d: dict, **kw):
    scene = pellucid.load_dict(d, base_dir=TEX)
    t0 = time.perf_counter()
    img, var, stats = pellucid.render_with_stats(scene, **kw)
    return np.asarray(img, dtype=np.float64), np.asarray(var, dtype=np.float64), time.perf_counter() - t0


def reference(material: dict, res, factor=8, spp=16, env=True) -> np.ndarray:
    big = (res[0] * factor, res[1] * factor)
    img, _, _ = render(plane_scene(material, big, spp, env=env))
    return img.reshape(res[1], factor, res[0], factor, 3).mean(axis=(1, 3))


def rmse(a, b) -> float:
    return float(np.sqrt(np.mean((a - b) ** 2)))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="fewer samples (a smoke run)")
    ap.add_argument("--threads", type=int, default=0)
    a = ap.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(OUT, exist_ok=True)
    make_textures()
    res = (96, 64)
    spp = 32 if a.quick else 128
    seeds = 8 if a.quick else 32
    tex_uv = [{"scale": [6, 6, 1]}]

    # 1. Bump error against the step Δu (in footprints).
    def bump_mat(m):
        return {"type": "lambertian", "reflectance": 0.7,
                "bump_map": {"type": "image", "filename": "bricks_height.exr", "to_uv": tex_uv},
                "bump_scale": 0.004, "bump_step_scale": m}
    ref = reference(bump_mat(1.0), res, spp=8 if a.quick else 16, env=False)
    rows = []
    for m in [1 / 16, 1 / 8, 1 / 4, 1 / 2, 1, 2, 4, 8, 16]:
        img, _, secs = render(plane_scene(bump_mat(m), res, spp, env=False), threads=a.threads)
        ones = [render(plane_scene(bump_mat(m), res, 1, seed=s, env=False), threads=a.threads)[0]
                for s in range(seeds)]
        var1 = float(np.mean(np.var(np.stack(ones), axis=0, ddof=1)))
        rows.append({"step_footprints": m, "rmse_vs_reference": rmse(img, ref), "variance_1spp": var1, "seconds": secs})
        print(f"bump step {m:7.4f} footprints: RMSE {rows[-1]['rmse_vs_reference']:.4f}  1-spp variance {var1:.5f}")
    with open(os.path.join(OUT, "bump_step.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    fig, ax = plt.subplots(figsize=(6, 4))
    ms = [r["step_footprints"] for r in rows]
    ax.loglog(ms, [r["rmse_vs_reference"] for r in rows], "o-", label=f"RMSE vs 8x supersampled reference ({spp} spp)")
    ax.loglog(ms, [np.sqrt(r["variance_1spp"]) for r in rows], "s--", label="noise: std. dev. at 1 spp")
    ax.axvline(1.0, color="k", lw=0.8, ls=":")
    ax.text(1.05, ax.get_ylim()[0] * 1.3, "our choice:\none footprint", fontsize=8)
    ax.set_xlabel("finite-difference step Δu (pixel footprints)")
    ax.set_ylabel("error")
    ax.set_title("Bump map: step too small aliases, too large blurs")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "bump_step.png"), dpi=120)

    # 2. Render time and error with and without MIP maps.
    def tex_mat(filt):
        return {"type": "lambertian",
                "reflectance": {"type": "image", "filename": "bricks.png", "filter": filt, "to_uv": tex_uv}}
    ref = reference(tex_mat("bilinear"), res, spp=8 if a.quick else 16)
    rows2 = []
    for filt in ["anisotropic", "trilinear", "bilinear", "nearest"]:
        render(plane_scene(tex_mat(filt), res, 4), threads=a.threads)  # warm the texture cache
        img, _, secs = render(plane_scene(tex_mat(filt), res, spp), threads=a.threads)
        ones = [render(plane_scene(tex_mat(filt), res, 1, seed=s), threads=a.threads)[0] for s in range(seeds)]
        var1 = float(np.mean(np.var(np.stack(ones), axis=0, ddof=1)))
        rows2.append({"filter": filt, "mip_mapped": filt in ("anisotropic", "trilinear"), "seconds": secs,
                      "rmse_vs_reference": rmse(img, ref), "variance_1spp": var1})
        print(f"filter {filt:12s}: {secs:6.2f} s  RMSE {rows2[-1]['rmse_vs_reference']:.4f}  1-spp variance {var1:.5f}")
    # Checkerboard: analytic box filter on and off.
    for filtered in [True, False]:
        mat = {"type": "lambertian", "reflectance": {"type": "checkerboard", "color0": 0.8, "color1": 0.1,
                                                     "filtered": filtered, "to_uv": [{"scale": [40, 40, 1]}]}}
        ones = [render(plane_scene(mat, res, 1, seed=s), threads=a.threads)[0] for s in range(seeds)]
        img, _, secs = render(plane_scene(mat, res, spp), threads=a.threads)
        var1 = float(np.mean(np.var(np.stack(ones), axis=0, ddof=1)))
        rows2.append({"filter": "checkerboard " + ("filtered" if filtered else "unfiltered"), "mip_mapped": filtered,
                      "seconds": secs, "rmse_vs_reference": float("nan"), "variance_1spp": var1})
        print(f"checkerboard filtered={filtered}: 1-spp variance {var1:.5f}")
    with open(os.path.join(OUT, "filtering.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows2[0]))
        w.writeheader()
        w.writerows(rows2)
    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    names = [r["filter"] for r in rows2]
    axs[0].bar(names[:4], [r["seconds"] for r in rows2[:4]], color=["C0", "C0", "C1", "C1"])
    axs[0].set_ylabel(f"render seconds ({spp} spp, {res[0]}x{res[1]})")
    axs[0].set_title("Render time: MIP-mapped (blue) vs not (orange)")
    axs[0].tick_params(axis="x", rotation=20)
    axs[1].bar(names, [r["variance_1spp"] for r in rows2], color=["C0", "C0", "C1", "C1", "C0", "C1"])
    axs[1].set_yscale("log")
    axs[1].set_ylabel("mean per-pixel variance at 1 spp")
    axs[1].set_title("Aliasing: filtered (blue) vs unfiltered (orange)")
    axs[1].tick_params(axis="x", rotation=30)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "filtering.png"), dpi=120)
    print("wrote", OUT)
    return 0


if __name__ == "__main__":
    sys.exit(main())

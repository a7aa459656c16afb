#!/usr/bin/env python3
"""What the environment map's importance sampling is worth (light/envmap.h).

    python bench/envmap_sampling.py [--map scenes/textures/sky.exr]
        [--scene bench/suite/aniso_metal.json --seeds 6 --spp 64]

1. Analytic: the relative variance of one-sample estimates of a map's integral (of the channel
   average L̄), and of the irradiance of a floor facing +y (the map's up, per channel, then averaged),
   Var[f/p]/E[f/p]², for three densities over the map's interpolation cells: constant inside each
   cell (weighted by the cell's integral of L̄ sin θ), and the bilinear interpolation of L̄ sin θ or
   of Y sin θ (Y the luminance, which pellucid samples) between the texels. Integrals are midpoint
   sums on 8 × 8 points per cell (exact for the bilinear densities). These are estimates with light
   sampling alone; the renders (2.) combine it with BSDF sampling by MIS.
2. Measured, with --scene: the mean over pixels of the per-pixel variance across --seeds renders
   divided by (mean² + 0.01), for pellucid's `pellucid-render` and, when bench/peers/setup_mitsuba.sh
   has been run, Mitsuba 3 `llvm_ad_rgb` on the same scene at the same spp; with `--variant
   nosphere` the scene's emitting shapes are removed first (the map alone).
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
sys.path.insert(0, str(ROOT / "python"))


def read(path: str) -> np.ndarray:
    import pellucid
    return np.asarray(pellucid.read_image(path), dtype=np.float64)[..., :3]


def analytic(map_path: str, sub: int = 8) -> None:
    img = read(map_path)
    h, w, _ = img.shape
    lbar = img.mean(axis=2)
    nv, nu = h - 1, w
    v = (np.arange(nv * sub) + 0.5) / (nv * sub)
    u = (np.arange(nu * sub) + 0.5) / (nu * sub)
    yf = v * nv
    y0 = np.minimum(np.floor(yf).astype(int), nv - 1)
    t = (yf - y0)[:, None]
    xf = u * nu
    x0 = np.minimum(np.floor(xf).astype(int), nu - 1)
    s = (xf - x0)[None, :]
    x1 = (x0 + 1) % w

    def bilinear(g: np.ndarray) -> np.ndarray:
        return ((1 - t) * ((1 - s) * g[y0][:, x0] + s * g[y0][:, x1]) +
                t * ((1 - s) * g[y0 + 1][:, x0] + s * g[y0 + 1][:, x1]))

    radiance = bilinear(lbar)
    sin = np.sin(np.pi * v)[:, None]
    duv = 1.0 / (nv * sub * nu * sub)
    dw = np.broadcast_to(2 * np.pi ** 2 * sin * duv, radiance.shape)
    cell_mean = (radiance * sin).reshape(nv, sub, nu, sub).mean(axis=(1, 3))
    constant = np.repeat(np.repeat(cell_mean, sub, axis=0), sub, axis=1)
    rows = np.sin(np.pi * np.arange(h) / (h - 1))[:, None]
    lum = img @ np.array([0.2126, 0.7152, 0.0722])
    densities = {"constant in each cell": constant, "bilinear L̄ sin θ": bilinear(lbar * rows),
                 "bilinear Y sin θ (pellucid)": bilinear(lum * rows)}
    cos = np.clip(np.cos(np.pi * v), 0.0, None)[:, None]
    channels = [bilinear(img[..., c]) for c in range(3)]
    print(f"{map_path}: {w} x {h}")

    def rel_var(f: np.ndarray, p: np.ndarray) -> float:
        ok = p > 0
        mean = (f * dw).sum()
        return float((f[ok] ** 2 / p[ok] * dw[ok]).sum() / mean ** 2 - 1.0)

    for name, p_uv in densities.items():
        p_uv = p_uv / (p_uv * duv).sum()
        p = p_uv / (2 * np.pi ** 2 * sin)
        floor = np.mean([rel_var(c * cos, p) for c in channels])
        print(f"  {name:28s} relative variance: map integral {rel_var(radiance, p):.4f}, floor irradiance {floor:.4f}")


def measured(scene: str, variant: str, seeds: int, spp: int, binary: str) -> None:
    d = json.loads(pathlib.Path(scene).read_text())
    if variant == "nosphere":
        d["shapes"] = [s for s in d["shapes"] if "emitter" not in s]
    with tempfile.TemporaryDirectory() as tmp:
        # Next to the scene, so that its relative file names resolve.
        path = pathlib.Path(scene).with_name(f"_envmap_sampling_{os.getpid()}.json")
        path.write_text(json.dumps(d))
        try:
            def stats(cmd) -> float:
                imgs = []
                for seed in range(1, seeds + 1):
                    out = os.path.join(tmp, f"{seed}.exr")
                    subprocess.run(cmd(seed, out), check=True, capture_output=True)
                    imgs.append(read(out))
                a = np.stack(imgs)
                m, var = a.mean(0), a.var(0, ddof=1)
                return float((var / (m ** 2 + 0.01)).mean())

            ours = stats(lambda s, o: [binary, str(path), "--spp", str(spp), "--seed", str(s), "--threads", "2", "-o", o])
            print(f"{scene} ({variant}), {spp} spp, {seeds} seeds: pellucid relative variance {ours:.4e}")
            py = ROOT / "bench" / ".venv-mitsuba" / "bin" / "python"
            if py.exists():
                mi = stats(lambda s, o: [str(py), str(ROOT / "bench/peers/mitsuba_runner.py"), str(path), "--variant",
                                         "llvm_ad_rgb", "--spp", str(spp), "--seed", str(s), "--threads", "2",
                                         "--out", o, "--quiet"])
                print(f"  Mitsuba 3 llvm_ad_rgb {mi:.4e}; pellucid / Mitsuba {ours / mi:.3f}")
        finally:
            path.unlink()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--map", default=str(ROOT / "scenes/textures/sky.exr"))
    ap.add_argument("--scene", default=None)
    ap.add_argument("--variant", choices=["full", "nosphere"], default="full")
    ap.add_argument("--seeds", type=int, default=6)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--binary", default=str(ROOT / "build/py/cpp/pellucid-render"))
    a = ap.parse_args()
    analytic(a.map)
    if a.scene:
        measured(a.scene, a.variant, a.seeds, a.spp, a.binary)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The far-field rule of the subsurface `auto` model (docs/subsurface.md, "Choosing the model"):
image error of the coated stand-in against the better dipole as the diffusion length ℓd shrinks
below the pixel footprint w.

    .venv/bin/python bench/subsurface_lod.py          # writes bench/results/subsurface/lod.{csv,png}

A sphere of radius 1, lit from the side by a directional light (a sharp terminator, where the
diffusion blurs light across it) plus a dim environment, seen by a 64 x 64 camera 4 units away;
the material's mfp is swept so that ℓd/w runs from 0.03 to 30 (albedo 0.8, η 1.4). At each point
both models render with two seeds at SPP samples per pixel. The squared bias of the stand-in (in
relMSE units) is estimated without the noise of either render,
    bias² ≈ relMSE(coated₁, dipole₁) − ½ relMSE(dipole₂, dipole₁) − ½ relMSE(coated₂, coated₁),
and compared with the variance of a 64-spp render of the better dipole (½ relMSE(dipole₂, dipole₁)
× SPP/64): where the bias is far below that noise, the stand-in is as good as the diffusion model at
a typical sample count, and faster.
"""
from __future__ import annotations

import csv
import pathlib
import sys
import time

import numpy as np

import pellucid
from pellucid.bench import rel_mse

OUT = pathlib.Path(__file__).resolve().parent / "results" / "subsurface"
SPP = 1024
RES = 48


def scene(model: str, mfp: float, seed: int) -> dict:
    return {
        "camera": {"type": "perspective", "fov": 30,
                   "to_world": [{"look_at": {"origin": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "film": {"width": RES, "height": RES},
        "sampler": {"sample_count": SPP, "seed": seed},
        "materials": {"m": {"type": "subsurface", "model": model, "albedo": [0.8, 0.8, 0.8], "mfp": mfp,
                            "int_ior": 1.4}},
        "shapes": [{"type": "sphere", "radius": 1, "material": "m"}],
        "lights": [{"type": "directional", "direction": [-1, 0, -0.3], "irradiance": 3},
                   {"type": "constant", "radiance": 0.05}],
    }


def render(model: str, mfp: float, seed: int):
    s = pellucid.load_dict(scene(model, mfp, seed))
    t = time.perf_counter()
    img = np.asarray(pellucid.render(s, threads=2))[..., :3]
    return img, time.perf_counter() - t, s


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    rows = []
    for mfp in np.geomspace(6e-5, 0.06, 10):
        d1, t_ref, s = render("better_dipole", float(mfp), 1)
        d2, _, _ = render("better_dipole", float(mfp), 2)
        c1, t_coat, _ = render("coated", float(mfp), 1)
        c2, _, _ = render("coated", float(mfp), 2)
        choice = s.subsurface_choices[0]
        ratio = choice["diffusion_length"] / choice["footprint"]
        var_d, var_c = 0.5 * rel_mse(d2, d1), 0.5 * rel_mse(c2, c1)
        bias2 = rel_mse(c1, d1) - var_d - var_c
        rows.append({"mfp": float(mfp), "ld": choice["diffusion_length"], "footprint": choice["footprint"],
                     "ld_over_w": ratio, "bias2_coated": bias2, "variance_dipole_64spp": var_d * SPP / 64,
                     "variance_coated_64spp": var_c * SPP / 64,
                     "time_dipole_s": t_ref, "time_coated_s": t_coat})
        print(f"ld/w {ratio:8.3f}  coated bias² {bias2:+.2e}  64-spp variance: dipole {var_d * SPP / 64:.2e} "
              f"coated {var_c * SPP / 64:.2e}  time ({SPP} spp) dipole {t_ref:.2f} s coated {t_coat:.2f} s", flush=True)
    with open(OUT / "lod.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    x = [r["ld_over_w"] for r in rows]
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.loglog(x, [max(r["bias2_coated"], 1e-7) for r in rows], "o-", label="coated: squared bias (relMSE)")
    ax.loglog(x, [r["variance_dipole_64spp"] for r in rows], "s--", label="better dipole: variance at 64 spp")
    ax.axvline(1.0, color="grey", lw=0.8, ls=":", label="auto threshold ℓd = w")
    ax.set_xlabel("diffusion length / pixel footprint (ℓd / w)")
    ax.set_ylabel("relMSE")
    ax.set_title("Far-field rule: coated Lambertian stand-in")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(OUT / "lod.png", dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())

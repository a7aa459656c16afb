"""Diffusion profiles against the searchlight random walk: bench/results/subsurface/<chart>.{csv,png}.
SPDX-License-Identifier: Apache-2.0

    .venv/bin/python bench/subsurface_profiles.py [--photons 4000000] [--slab-photons 10000000] [--threads 0]
        [--out-dir bench/results/subsurface]

Writes
- profiles_Rr.png: R(r) of the dipole, the better dipole and the random walk (total and its multiple-
  scattering part) against r in mean free paths, at albedos 0.5, 0.9 and 0.99;
- profiles_error.csv/.png: the total's relative error and each ring's relative error against the walk,
  for albedos 0.5 to 0.999;
- thin_slab.csv/.png: R(∞) − R(T) of slabs of thickness T/ℓd = 0.25 … 4 at albedo 0.99, with weighted
  fits C·e^(−k T/ℓd) over T/ℓd in [0.25, 4] ("full"), [0.5, 2.5] ("test", the range of
  tests/cpp/bssrdf/test_searchlight.cpp) and [1.5, 4] ("tail"), and the slab transmittance with its rate.

The medium: η = 1.33, g = 0, σt = 1 (lengths are in mean free paths), normal searchlight, results per
entered photon (pellucid.bssrdf.searchlight). Fixed seeds; about two minutes on two cores.
R(∞) − R(T) is measured with common random numbers: each slab runs with the half-space's seed, so
the paths agree until they first reach depth T, and the paired difference per chunk of 4096 photons
gives its standard error.
"""
from __future__ import annotations

import argparse
import csv
import math
import pathlib
import time
from typing import Dict, List, Sequence, Tuple

import numpy as np

import pellucid
from pellucid import bssrdf

HERE = pathlib.Path(__file__).resolve().parent
ETA = 1.33
ALBEDOS = (0.5, 0.8, 0.9, 0.95, 0.99, 0.999)
PLOTTED = (0.5, 0.9, 0.99)
TAUS = (0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0)
SLAB_ALBEDO = 0.99
EDGES = np.concatenate([[0.0], np.geomspace(0.02, 64.0, 36)])
LABEL = {"dipole": "dipole (Jensen 2001)", "better_dipole": "better dipole (d'Eon 2012)"}


def ring_means(p: bssrdf.Profile, edges: np.ndarray) -> np.ndarray:
    """Mean R over each ring [a, b) (64-point Gauss–Legendre in r of 2πr R(r), divided by the area)."""
    x, w = np.polynomial.legendre.leggauss(64)
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        r = 0.5 * (a + b) + 0.5 * (b - a) * x
        out.append(np.sum(0.5 * (b - a) * w * 2 * np.pi * r * p.eval(r).astype(np.float64)) / (np.pi * (b * b - a * a)))
    return np.array(out)


def walk_albedo(albedo: float, photons: int, threads: int) -> Dict[str, np.ndarray]:
    return bssrdf.searchlight(1.0 - albedo, albedo, 0.0, ETA, math.inf, photons, seed=17, r_edges=list(EDGES),
                              threads=threads)


def accuracy(photons: int, threads: int, out: pathlib.Path, plt) -> List[Dict[str, float]]:
    rows: List[Dict[str, float]] = []
    curves = {}
    for a in ALBEDOS:
        t0 = time.perf_counter()
        w = walk_albedo(a, photons, threads)
        n = w["photons"]
        R, R_se = w["reflectance"], math.sqrt(w["reflectance"] * (1 - w["reflectance"]) / n)
        area = np.pi * np.diff(EDGES ** 2)
        ring_se = np.sqrt(w["counts"]) / (n * area)
        print(f"albedo {a}: R = {R:.5f} ± {R_se:.5f} ({time.perf_counter() - t0:.1f} s)")
        for m in bssrdf.MODELS:
            p = bssrdf.profile(m, 1.0 - a, a, 0.0, ETA)
            rings = ring_means(p, EDGES)
            rows.append(dict(albedo=a, model=m, quantity="total", r_lo=0.0, r_hi=math.inf, walk=R, walk_se=R_se,
                             model_value=p.total, rel_error=p.total / R - 1))
            for k in range(len(EDGES) - 1):
                if w["counts"][k] >= 100:  # rings with a relative error of the walk below 10 %
                    rows.append(dict(albedo=a, model=m, quantity="ring", r_lo=EDGES[k], r_hi=EDGES[k + 1],
                                     walk=w["exitance"][k], walk_se=ring_se[k], model_value=rings[k],
                                     rel_error=rings[k] / w["exitance"][k] - 1))
            curves[(a, m)] = rings
        curves[(a, "walk")] = (w["exitance"], ring_se, w["exitance"] - w["exitance_single"])
    with open(out / "profiles_error.csv", "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0]))
        wr.writeheader()
        wr.writerows(rows)

    mid = np.sqrt(EDGES[:-1] * EDGES[1:])
    mid[0] = 0.5 * EDGES[1]
    fig, axes = plt.subplots(1, len(PLOTTED), figsize=(5 * len(PLOTTED), 4.2), sharey=False)
    for ax, a in zip(axes, PLOTTED):
        wv, wse, wms = curves[(a, "walk")]
        ok = wv > 0
        ax.errorbar(mid[ok], wv[ok], yerr=2 * wse[ok], fmt="o", ms=3, color="k", label="random walk (±2σ)")
        ax.plot(mid[wms > 0], wms[wms > 0], ".", color="0.55", label="random walk, multiple scattering")
        for m, c in zip(bssrdf.MODELS, ("C0", "C3")):
            ax.plot(mid, curves[(a, m)], "-", color=c, label=LABEL[m])
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_ylim(max(1e-9, wv[ok].min() / 3), wv.max() * 2)
        ax.set_title(f"albedo {a}, η = {ETA}, g = 0")
        ax.set_xlabel("r / mean free path")
        ax.set_ylabel("R(r) per unit area (ring mean)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "profiles_Rr.png", dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    for m, c in zip(bssrdf.MODELS, ("C0", "C3")):
        t = [r for r in rows if r["model"] == m and r["quantity"] == "total"]
        axes[0].plot([1 - r["albedo"] for r in t], [100 * r["rel_error"] for r in t], "o-", color=c, label=LABEL[m])
    axes[0].set_xscale("log")
    axes[0].invert_xaxis()
    axes[0].axhline(0, color="k", lw=0.5)
    axes[0].set_xlabel("1 − albedo")
    axes[0].set_ylabel("total: model / walk − 1 (%)")
    axes[0].legend(fontsize=8)
    axes[0].set_title("total diffuse reflectance")
    for ax, m in zip(axes[1:], bssrdf.MODELS):
        for a in ALBEDOS:
            rr = [r for r in rows if r["model"] == m and r["quantity"] == "ring" and r["albedo"] == a]
            ax.plot([math.sqrt(max(r["r_lo"], 0.01) * r["r_hi"]) for r in rr], [100 * r["rel_error"] for r in rr], "-",
                    label=f"albedo {a}")
        ax.set_xscale("log")
        ax.set_ylim(-100, 200)
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xlabel("r / mean free path")
        ax.set_ylabel("ring: model / walk − 1 (%)")
        ax.set_title(LABEL[m])
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "profiles_error.png", dpi=110)
    plt.close(fig)
    return rows


def weighted_fit(x: Sequence[float], y: Sequence[float], se: Sequence[float]) -> Tuple[float, float, float]:
    """ln y = ln C − k x by weighted least squares (weights (y/se)², the inverse variance of ln y):
    (C, k, standard error of k)."""
    x, y, se = (np.asarray(v, dtype=float) for v in (x, y, se))
    w = (y / se) ** 2
    A = np.stack([np.ones_like(x), -x], axis=1)
    cov = np.linalg.inv(A.T @ (A * w[:, None]))
    lnC, k = cov @ (A.T @ (w * np.log(y)))
    return math.exp(lnC), k, math.sqrt(cov[1, 1])


def thin_slab(photons: int, threads: int, out: pathlib.Path, plt) -> Dict[str, float]:
    a = SLAB_ALBEDO
    ld = bssrdf.profile("dipole", 1 - a, a, 0.0, ETA).diffusion_length
    dip = bssrdf.profile("dipole", 1 - a, a, 0.0, ETA).total
    half = bssrdf.searchlight(1 - a, a, 0.0, ETA, math.inf, photons, seed=11, threads=threads)
    rows = []
    for tau in TAUS:
        t0 = time.perf_counter()
        s = bssrdf.searchlight(1 - a, a, 0.0, ETA, tau * ld, photons, seed=11, threads=threads)
        d = half["chunk_reflectance"] - s["chunk_reflectance"]  # paired: same paths until depth T
        se = d.std(ddof=1) / math.sqrt(len(d))
        T = s["transmittance"]
        rows.append(dict(T_over_ld=tau, thickness_mfp=tau * ld, R_slab=s["reflectance"], T_slab=T,
                         T_se=math.sqrt(T * (1 - T) / photons), deficit=half["reflectance"] - s["reflectance"],
                         deficit_se=se, dipole_error=dip - s["reflectance"]))
        print(f"T/ld {tau}: R {s['reflectance']:.5f} deficit {rows[-1]['deficit']:.3e} ± {se:.1e} "
              f"({time.perf_counter() - t0:.1f} s)")
    fits = {}
    for name, lo, hi in (("full", 0.25, 4.0), ("test", 0.5, 2.5), ("tail", 1.5, 4.0)):
        rr = [r for r in rows if lo <= r["T_over_ld"] <= hi and r["deficit"] > 2 * r["deficit_se"]]
        fits[name] = weighted_fit([r["T_over_ld"] for r in rr], [r["deficit"] for r in rr], [r["deficit_se"] for r in rr])
    fits["transmittance"] = weighted_fit([r["T_over_ld"] for r in rows], [r["T_slab"] for r in rows],
                                         [r["T_se"] for r in rows])
    with open(out / "thin_slab.csv", "w", newline="") as f:
        f.write(f"# albedo {a}, eta {ETA}, g 0, diffusion length {ld:.6g} mfp, R(inf) {half['reflectance']:.6f}, "
                f"dipole total {dip:.6f}, {photons} photons per slab\n")
        for name, (C, k, kse) in fits.items():
            f.write(f"# fit {name}: C = {C:.4g}, k = {k:.4f} +- {kse:.4f}\n")
        wr = csv.DictWriter(f, fieldnames=list(rows[0]))
        wr.writeheader()
        wr.writerows(rows)

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    x = np.array([r["T_over_ld"] for r in rows])
    ax.errorbar(x, [r["deficit"] for r in rows], yerr=[2 * r["deficit_se"] for r in rows], fmt="o", color="C3",
                label="R(∞) − R(T), random walk (±2σ)")
    xx = np.linspace(0, 4.2, 50)
    for name, style, span in (("tail", "-", "[1.5, 4]"), ("test", ":", "[0.5, 2.5]"), ("full", "-.", "[0.25, 4]")):
        C, k, kse = fits[name]
        ax.plot(xx, C * np.exp(-k * xx), style, color="C3", lw=1, label=f"fit over {span}: {C:.2f}·e^(−{k:.2f}±{kse:.2f} T/ℓd)")
    ax.plot(x, [r["T_slab"] for r in rows], "s", color="C0", label="transmittance T(T)")
    C, k, kse = fits["transmittance"]
    ax.plot(xx, C * np.exp(-k * xx), "--", color="C0", label=f"fit {C:.2f}·e^(−{k:.2f} T/ℓd)")
    ax.set_yscale("log")
    ax.set_xlabel("slab thickness T / diffusion length ℓd")
    ax.set_ylabel("per entered photon")
    ax.set_title(f"thin slabs: albedo {a}, η = {ETA}, ℓd = {ld:.2f} mfp")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "thin_slab.png", dpi=110)
    plt.close(fig)
    return {name: k for name, (C, k, kse) in fits.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--photons", type=int, default=4_000_000, help="photons per albedo")
    ap.add_argument("--slab-photons", type=int, default=10_000_000, help="photons per slab thickness")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--out-dir", type=pathlib.Path, default=HERE / "results" / "subsurface")
    args = ap.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    args.out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    rows = accuracy(args.photons, args.threads, args.out_dir, plt)
    for r in rows:
        if r["quantity"] == "total":
            print(f"  {r['model']:>13} albedo {r['albedo']}: total {r['model_value']:.5f} vs walk {r['walk']:.5f} "
                  f"({100 * r['rel_error']:+.2f} %)")
    ks = thin_slab(args.slab_photons, args.threads, args.out_dir, plt)
    print("thin-slab rates:", {k: round(v, 4) for k, v in ks.items()})
    print(f"pellucid {pellucid.__version__}: {time.perf_counter() - t0:.0f} s; wrote {args.out_dir}")


if __name__ == "__main__":
    main()

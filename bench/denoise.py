"""What denoising does to error and to bias, against render time.

For each scene (rendered at a reduced size with filter sampling and a one-pixel box filter, so that
pixel noise is independent between pixels as the denoiser expects), at spp 1, 2, 4, ..., it renders
K independent images (seeds 1..K) with the albedo and normal AOVs and measures, against a
reference rendered at many more samples:

- error: the mean over the K renders of relMSE (pellucid.image.rel_mse) of the noisy image, the
  denoised image without guides, and the denoised image with the albedo + normal guides;
- bias: relMSE of the mean of the K images. For the unbiased noisy renders it falls as 1/(K·spp)
  (the mean is a render of K·spp samples); for the denoised ones it stops at the squared bias of
  the denoiser, which averaging more renders cannot remove.

Time is the wall time per render: the beauty render, plus the AOV pass for the guided curve, plus
the denoiser's own time for both denoised curves (Open Image Denoise on the CPU, through pyoidn).

    .venv/bin/pip install pyoidn   # the optional extra: pip install "pellucid[denoise]"
    .venv/bin/python bench/denoise.py [--size 128] [--renders 8] [--max-spp 128] [--ref-spp 2048] \
        [--out bench/results/denoise]

Writes denoise.csv, denoise.png and prints a table. Timings are of one run on one machine.
"""
from __future__ import annotations

import argparse
import csv
import json
import pathlib
import time
from typing import Dict, List

import numpy as np

import pellucid
from pellucid.image import rel_mse

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCENES = ["cornell_box", "veach_mis", "env_spheres"]


def load(name: str, size: int) -> pellucid.Scene:
    d = json.loads((ROOT / "scenes" / f"{name}.json").read_text())
    w, h = d["film"]["width"], d["film"]["height"]
    d["film"] = {"width": size, "height": max(8, round(size * h / w)), "filter": {"type": "box", "radius": 0.5}}
    return pellucid.load_dict(d, ROOT / "scenes")


def run_scene(name: str, args: argparse.Namespace) -> List[Dict[str, float]]:
    scene = load(name, args.size)
    ref = np.asarray(pellucid.render(scene, spp=args.ref_spp, seed=10_000, threads=args.threads), np.float64)
    rows = []
    spp = 1
    while spp <= args.max_spp:
        acc = {k: [] for k in ("beauty_s", "aov_s", "dn_s", "dng_s", "noisy", "dn", "dng")}
        images = {"noisy": [], "dn": [], "dng": []}
        for k in range(args.renders):
            r = pellucid.render(scene, spp=spp, seed=1 + k, threads=args.threads, aovs=["albedo", "normal"])
            t0 = time.perf_counter()
            dn = pellucid.denoise(r.image)
            t1 = time.perf_counter()
            dng = pellucid.denoise(r.image, r["albedo"], r["normal"])
            t2 = time.perf_counter()
            acc["beauty_s"].append(r.stats["seconds"])
            acc["aov_s"].append(r.stats["aov_seconds"])
            acc["dn_s"].append(t1 - t0)
            acc["dng_s"].append(t2 - t1)
            for key, img in (("noisy", r.image), ("dn", dn), ("dng", dng)):
                acc[key].append(rel_mse(img, ref))
                images[key].append(np.asarray(img, np.float64))
        row = {"scene": name, "spp": spp, "renders": args.renders,
               "seconds_beauty": float(np.mean(acc["beauty_s"])), "seconds_aov": float(np.mean(acc["aov_s"])),
               "seconds_denoise": float(np.mean(acc["dn_s"])), "seconds_denoise_guided": float(np.mean(acc["dng_s"]))}
        for key, label in (("noisy", "noisy"), ("dn", "denoised"), ("dng", "denoised_guided")):
            row[f"relmse_{label}"] = float(np.mean(acc[key]))
            row[f"relmse_mean_of_renders_{label}"] = rel_mse(np.mean(images[key], axis=0), ref)
        rows.append(row)
        print(f"{name:12s} spp {spp:4d}  t {row['seconds_beauty']:.3f}+{row['seconds_aov']:.3f}+"
              f"{row['seconds_denoise_guided']:.3f} s  relMSE noisy {row['relmse_noisy']:.3e} "
              f"denoised {row['relmse_denoised']:.3e} guided {row['relmse_denoised_guided']:.3e}  "
              f"mean of {args.renders}: noisy {row['relmse_mean_of_renders_noisy']:.3e} "
              f"denoised {row['relmse_mean_of_renders_denoised']:.3e} "
              f"guided {row['relmse_mean_of_renders_denoised_guided']:.3e}", flush=True)
        spp *= 2
    return rows


def chart(rows: List[Dict[str, float]], path: pathlib.Path, renders: int) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    fig, axes = plt.subplots(2, len(scenes), figsize=(4.6 * len(scenes), 8.2), squeeze=False)
    for j, name in enumerate(scenes):
        rs = [r for r in rows if r["scene"] == name]
        t_noisy = [r["seconds_beauty"] for r in rs]
        t_dn = [r["seconds_beauty"] + r["seconds_denoise"] for r in rs]
        t_dng = [r["seconds_beauty"] + r["seconds_aov"] + r["seconds_denoise_guided"] for r in rs]
        curves = (("noisy", t_noisy, "noisy (unbiased)", "k"), ("denoised", t_dn, "denoised", "C0"),
                  ("denoised_guided", t_dng, "denoised, albedo+normal guides", "C3"))
        for row_i, prefix, title in ((0, "relmse_", "error of one render"),
                                     (1, "relmse_mean_of_renders_", f"error of the mean of {renders} renders (bias)")):
            ax = axes[row_i][j]
            for key, t, label, colour in curves:
                ax.loglog(t, [r[prefix + key] for r in rs], "o-", color=colour, label=label, ms=3)
                if key == "noisy":
                    for tt, r in zip(t, rs):
                        ax.annotate(f"{r['spp']}", (tt, r[prefix + key]), fontsize=6, xytext=(2, -8),
                                    textcoords="offset points")
            ax.set_title(f"{name}: {title}", fontsize=9)
            ax.set_xlabel("seconds per render (labels: spp)")
            ax.set_ylabel("relMSE")
            ax.grid(True, which="both", alpha=0.3)
            if j == 0:
                ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", type=int, default=128, help="image width in pixels (height keeps the aspect)")
    p.add_argument("--renders", type=int, default=8, help="independent renders per spp (K)")
    p.add_argument("--max-spp", type=int, default=128)
    p.add_argument("--ref-spp", type=int, default=2048)
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--scenes", default=",".join(SCENES))
    p.add_argument("--out", default=str(ROOT / "bench" / "results" / "denoise"))
    args = p.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows: List[Dict[str, float]] = []
    for name in args.scenes.split(","):
        rows += run_scene(name, args)
    with open(out / "denoise.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    chart(rows, out / "denoise.png", args.renders)
    print(f"wrote {out / 'denoise.csv'} and {out / 'denoise.png'}")


if __name__ == "__main__":
    main()

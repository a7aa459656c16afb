"""Image charts of subsurface scattering: bench/results/subsurface/.
SPDX-License-Identifier: Apache-2.0

    .venv/bin/python bench/subsurface_charts.py [--ref-spp 512] [--max-spp 1024] [--rung-cap 20]
        [--threads 2] [--seed 0] [--no-mitsuba] [--out-dir bench/results/subsurface] [--cache-dir bench/cache]

On scenes/subsurface.json (a torus, a thin slab, a small and a large sphere of one `subsurface`
material) it renders the material's four models, set on the material: `dipole`, `better_dipole`,
`random_walk` and `auto` (which picks the random walk for the thin slab and small sphere and the
better dipole for the torus and the large sphere; the render log says so). Writes:

* ``image_error_vs_time.csv/.png``: relMSE against render time, one line per model, on a ladder of
  1, 2, 4, ... spp (each rung stops the ladder once it took longer than ``--rung-cap`` seconds, or at
  ``--max-spp``). The reference is the random walk (the ground truth) at ``--ref-spp``, rendered
  once and cached in ``--cache-dir`` (git-ignored) under a hash of the scene, the settings and the
  pellucid version. relMSE = mean (x - r)^2 / (r^2 + 0.01) (pellucid.bench.rel_mse). The diffusion
  models level off at their bias; ``bias`` in the CSV is the relMSE less the image's own noise
  (mean Var/(r^2 + 0.01) from the render's variance) and the reference's noise floor.
* ``auto_speedup.csv/.md``: the time auto and the random walk need to reach a few relMSE levels above
  auto's bias floor (interpolated in log-log between rungs) and their ratio.
* ``models_equal_time.png``: the four models and the reference, each model rendered for the same
  time budget, full frames and crops.
* With Mitsuba 3 set up (bench/peers/setup_mitsuba.sh): bench/scenes/subsurface_sphere.json and its
  Mitsuba twin bench/scenes/subsurface_sphere.xml (a `dielectric` BSDF over a `homogeneous` interior
  medium, `volpath`, `llvm_ad_rgb`, 16 passes for the variance, run by bench/suite/mitsuba_twin.py),
  against pellucid's `random_walk`, `better_dipole` and `dipole`: ``mitsuba_side_by_side.png``
  and ``mitsuba_compare.csv`` (relMSE of ours against Mitsuba's image, and the per-pixel z-test
  pass fraction of pellucid.bench.z_test, two-sided alpha 0.01, Sidak-corrected). Without Mitsuba
  this part is skipped with a message.

Renders run in this process with ``--threads`` threads, each after an untimed 1-spp warm-up; the time
is pellucid's own (``stats["seconds"]``). Every seed is fixed: the images repeat exactly, the times
do not (they depend on the machine's load, which the summary records).
"""
from __future__ import annotations

import argparse
import csv
import json
import logging
import math
import pathlib
import subprocess
import sys
import tempfile
import time
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
SCENE = ROOT / "scenes" / "subsurface.json"
MI_JSON = HERE / "scenes" / "subsurface_sphere.json"
MI_XML = HERE / "scenes" / "subsurface_sphere.xml"
MODELS = ("dipole", "better_dipole", "random_walk", "auto")
OBJECTS = {"shapes[1]": "torus", "shapes[2]": "slab", "shapes[3]": "small sphere", "shapes[4]": "large sphere"}
STYLE = {"dipole": ("tab:orange", "s"), "better_dipole": ("tab:green", "D"), "random_walk": ("tab:blue", "o"),
         "auto": ("tab:red", "^")}
EXPOSURE = 1.6  # the charts' tone mapping


def log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def with_model(scene: dict, model: str, material: str) -> dict:
    d = json.loads(json.dumps(scene))
    d["materials"][material]["model"] = model
    return d


def render(scene: dict, base_dir: pathlib.Path, spp: Optional[int], seed: int, threads: int,
           budget: Optional[float] = None) -> Tuple[np.ndarray, np.ndarray, dict]:
    """One warm, timed render: (mean, variance of the mean, stats)."""
    import pellucid

    sc = pellucid.load_dict(scene, base_dir=base_dir)
    pellucid.render_with_stats(sc, spp=1, seed=seed + 1_000_003, threads=threads)  # untimed warm-up
    img, var, st = pellucid.render_with_stats(sc, spp=spp, seed=seed, threads=threads, time_budget=budget)
    if st["invalid_samples"]:
        raise RuntimeError(f"{st['invalid_samples']} invalid samples")
    return np.array(img, dtype=np.float64), np.array(var, dtype=np.float64), st


def noise(img: np.ndarray, var: np.ndarray, ref: np.ndarray) -> float:
    """The relMSE an unbiased image with this variance has on average (pellucid.bench's floor)."""
    from pellucid.bench import ref_relmse_floor

    return ref_relmse_floor(ref, var)


# ------------------------------------------------------------------------------------- reference
def reference(scene: dict, args) -> Tuple[np.ndarray, np.ndarray, dict]:
    import pellucid
    from pellucid.bench import reference_key

    d = with_model(scene, "random_walk", "wax")
    settings = {"renderer": "ours", "spp": args.ref_spp, "seed": args.seed + 555, "version": pellucid.__version__,
                "mesh": (SCENE.parent / "meshes" / "torus.obj").read_text()}
    key = reference_key(d, settings)
    cache = pathlib.Path(args.cache_dir)
    cache.mkdir(parents=True, exist_ok=True)
    img_p, var_p, meta_p = (cache / f"subsurface_ref_{key}.exr", cache / f"subsurface_ref_{key}.var.exr",
                            cache / f"subsurface_ref_{key}.json")
    if img_p.exists() and var_p.exists() and meta_p.exists():
        log(f"reference: cached {img_p}")
        return (np.array(pellucid.read_image(img_p), np.float64), np.array(pellucid.read_image(var_p), np.float64),
                json.loads(meta_p.read_text()))
    log(f"reference: random_walk, {args.ref_spp} spp (cached as {img_p.name}) ...")
    sc = pellucid.load_dict(d, base_dir=SCENE.parent)
    img, var, st = pellucid.render_with_stats(sc, spp=args.ref_spp, seed=args.seed + 555, threads=args.threads)
    if st["invalid_samples"]:
        raise RuntimeError(f"reference: {st['invalid_samples']} invalid samples")
    meta = {"model": "random_walk", "spp": args.ref_spp, "seed": args.seed + 555, "seconds": st["seconds"],
            "threads": args.threads, "version": pellucid.__version__}
    pellucid.write_image(img_p, np.array(img))
    pellucid.write_image(var_p, np.array(var))
    meta_p.write_text(json.dumps(meta, indent=1))
    log(f"reference: {st['seconds']:.1f} s")
    return np.array(img, np.float64), np.array(var, np.float64), meta


# ------------------------------------------------------------------------------------- the ladder
def ladder(scene: dict, ref: np.ndarray, ref_floor: float, args) -> List[Dict]:
    from pellucid.bench import rel_mse

    rows = []
    for model in MODELS:
        d = with_model(scene, model, "wax")
        spp, i = 1, 0
        while spp <= args.max_spp:
            img, var, st = render(d, SCENE.parent, spp, args.seed + 7919 * i, args.threads)
            e = rel_mse(img, ref)
            # One sample per pixel has no variance estimate: its noise and bias are left blank.
            own = noise(img, var, ref) if spp > 1 else None
            rows.append({"model": model, "spp": spp, "seconds": float(st["seconds"]), "relmse": e,
                         "image_noise": own, "ref_floor": ref_floor,
                         "bias": None if own is None else e - own - ref_floor,
                         "threads": args.threads, "seed": args.seed + 7919 * i})
            log(f"{model:14s} {spp:5d} spp {st['seconds']:8.3f} s relMSE {e:.4e} (own noise {own or 0:.2e})")
            if st["seconds"] > args.rung_cap:
                break
            spp, i = spp * 2, i + 1
    return rows


def plateau(rows: List[Dict], model: str) -> float:
    """A model's bias floor: the relMSE at its largest spp less both images' noise (at least 0)."""
    last = max((r for r in rows if r["model"] == model), key=lambda r: r["spp"])
    return max(last["bias"] or 0.0, 0.0)


def time_to(rows: List[Dict], model: str, level: float) -> Optional[float]:
    """The render time at which the model's relMSE first falls to `level`, interpolated in log-log
    between the two rungs around that crossing; None when its ladder never reaches the level or
    starts below it."""
    pts = sorted((r["seconds"], r["relmse"]) for r in rows if r["model"] == model)
    if not pts or pts[0][1] <= level:
        return None
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if e0 > level >= e1:
            f = (math.log(level) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    return None


def speedup(rows: List[Dict]) -> List[Dict]:
    floor = plateau(rows, "auto")
    ref_floor = rows[0]["ref_floor"]
    rw = [r["relmse"] for r in rows if r["model"] == "random_walk"]
    au = [r["relmse"] for r in rows if r["model"] == "auto"]
    # Levels where auto's bias is at most a third of the error, which both ladders cross.
    lo = max(3.0 * (floor + ref_floor), min(rw) * 1.05, min(au) * 1.05)
    hi = min(max(rw), max(au)) / 1.05
    if lo >= hi:
        return []
    out = []
    for k in range(4):
        level = lo * (hi / lo) ** (k / 3.0)
        ta, tr = time_to(rows, "auto", level), time_to(rows, "random_walk", level)
        if ta and tr:
            out.append({"relmse": level, "auto_seconds": ta, "random_walk_seconds": tr, "speedup": tr / ta})
    return out


# ------------------------------------------------------------------------------------- figures
def tonemap(img: np.ndarray) -> np.ndarray:
    from pellucid.bench import tonemap as tm

    return tm(img, EXPOSURE)


def write_csv(path: pathlib.Path, rows: Sequence[Dict]) -> None:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def plot_error(rows: List[Dict], ref_meta: dict, path: pathlib.Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.6, 4.6))
    for m in MODELS:
        rr = sorted((r for r in rows if r["model"] == m), key=lambda r: r["spp"])
        c, mk = STYLE[m]
        ax.loglog([r["seconds"] for r in rr], [r["relmse"] for r in rr], marker=mk, color=c, label=m)
        for r in rr[::2]:
            ax.annotate(str(r["spp"]), (r["seconds"], r["relmse"]), fontsize=6, xytext=(3, 3),
                        textcoords="offset points", color=c)
        if m != "random_walk":
            ax.axhline(plateau(rows, m) + rows[0]["ref_floor"], color=c, ls="--", lw=0.8, alpha=0.6)
    ax.axhline(rows[0]["ref_floor"], color="k", ls=":", lw=1, label="reference noise floor")
    ax.set_xlabel("render time [s] (2 threads)")
    ax.set_ylabel("relMSE  (x-r)²/(r²+0.01)")
    ax.set_title(f"scenes/subsurface.json, {rows[0]['spp']}-{max(r['spp'] for r in rows)} spp against the "
                 f"random walk at {ref_meta['spp']} spp\n(dashed: each diffusion model's bias + the reference "
                 "floor; numbers: spp)", fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def plot_equal_time(tiles: List[Tuple[str, np.ndarray]], path: pathlib.Path, title: str) -> None:
    """Full frames in the first row, 2x crops of the slab and small sphere and of the torus below."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    H, W = tiles[0][1].shape[:2]
    crops = [(int(0.36 * W), int(0.28 * H), int(0.30 * W), int(0.72 * H)),   # slab and small sphere
             (int(0.58 * W), int(0.10 * H), int(0.36 * W), int(0.60 * H))]   # torus
    n = len(tiles)
    fig, axes = plt.subplots(3, n, figsize=(2.3 * n, 2.3 * 3 * 0.78 + 0.7), squeeze=False)
    for j, (lab, im) in enumerate(tiles):
        axes[0][j].imshow(tonemap(im), interpolation="nearest")
        axes[0][j].set_title(lab, fontsize=7)
        for k, (x, y, w, h) in enumerate(crops):
            axes[k + 1][j].imshow(tonemap(im[y:y + h, x:x + w]), interpolation="nearest")
    for ax in axes.ravel():
        ax.axis("off")
    fig.suptitle(title, fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=68)
    plt.close(fig)


def equal_time(scene: dict, ref: np.ndarray, rows: List[Dict], args) -> List[Tuple[str, np.ndarray]]:
    from pellucid.bench import rel_mse

    budget = args.equal_time
    tiles = []
    for m in MODELS:
        img, _, st = render(with_model(scene, m, "wax"), SCENE.parent, None, args.seed + 31, args.threads, budget)
        tiles.append((f"{m}\n{st['seconds']:.1f} s, {st['spp']} spp\nrelMSE {rel_mse(img, ref):.2e}", img))
        log(f"equal time {m}: {st['spp']} spp in {st['seconds']:.2f} s")
    return tiles


# ------------------------------------------------------------------------------------- Mitsuba
def mitsuba(args, out: pathlib.Path) -> Optional[List[Dict]]:
    import pellucid
    from pellucid.bench import mitsuba_python, rel_mse, ref_relmse_floor, z_test

    py = mitsuba_python()
    if py is None or args.no_mitsuba:
        log("Mitsuba 3 is not set up (bench/peers/setup_mitsuba.sh) or --no-mitsuba: the Mitsuba comparison is "
            "skipped")
        return None
    base = json.loads(MI_JSON.read_text())
    w, h = base["film"]["width"], base["film"]["height"]
    with tempfile.TemporaryDirectory() as td:
        exr, rep = pathlib.Path(td) / "mi.exr", pathlib.Path(td) / "mi.json"
        cmd = [str(py), str(HERE / "suite" / "mitsuba_twin.py"), str(MI_XML), "--variant", "llvm_ad_rgb",
               "--spp", str(args.mitsuba_spp), "--width", str(w), "--height", str(h), "--passes", "16",
               "--seed", str(args.seed), "--threads", str(args.threads), "--out", str(exr), "--json-report", str(rep)]
        log(f"Mitsuba 3 volpath llvm_ad_rgb: {args.mitsuba_spp} spp in 16 passes ...")
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"Mitsuba failed:\n{(r.stderr or r.stdout)[-3000:]}")
        mi_img = np.array(pellucid.read_image(exr), np.float64)[..., :3]
        mi_var = np.array(pellucid.read_image(exr.with_suffix(".var.exr")), np.float64)[..., :3]
        mi_rep = json.loads(rep.read_text())
    if mi_rep["nonfinite"]:
        raise RuntimeError(f"Mitsuba: {mi_rep['nonfinite']} non-finite values")
    mi_floor = ref_relmse_floor(mi_img, mi_var)
    rows = [{"renderer": "mitsuba volpath llvm_ad_rgb", "model": "dielectric + homogeneous", "spp": args.mitsuba_spp,
             "seconds": mi_rep["seconds"], "relmse_vs_mitsuba": 0.0, "mitsuba_noise_floor": mi_floor,
             "own_noise": mi_floor, "z_pass_fraction": 1.0, "critical_z": 0.0,
             "mean_r": mi_img[..., 0].mean(), "mean_g": mi_img[..., 1].mean(), "mean_b": mi_img[..., 2].mean()}]
    images = {"mitsuba": mi_img}
    for model in ("random_walk", "better_dipole", "dipole"):
        img, var, st = render(with_model(base, model, "sss"), MI_JSON.parent, args.mitsuba_ours_spp, args.seed + 77,
                              args.threads)
        frac, zc = z_test(img, var, mi_img, mi_var)
        rows.append({"renderer": "pellucid path", "model": model, "spp": args.mitsuba_ours_spp,
                     "seconds": float(st["seconds"]), "relmse_vs_mitsuba": rel_mse(img, mi_img),
                     "mitsuba_noise_floor": mi_floor, "own_noise": noise(img, var, mi_img), "z_pass_fraction": frac,
                     "critical_z": zc, "mean_r": img[..., 0].mean(), "mean_g": img[..., 1].mean(),
                     "mean_b": img[..., 2].mean()})
        images[model] = img
        log(f"pellucid {model:14s} {args.mitsuba_ours_spp} spp {st['seconds']:.2f} s: relMSE vs Mitsuba "
            f"{rows[-1]['relmse_vs_mitsuba']:.3e}, z-test pass {frac:.4f}")
    write_csv(out / "mitsuba_compare.csv", rows)
    plot_mitsuba(images, rows, out / "mitsuba_side_by_side.png")
    return rows


def plot_mitsuba(images: Dict[str, np.ndarray], rows: List[Dict], path: pathlib.Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    by = {r["model"]: r for r in rows}
    mi = images["mitsuba"]
    lum = lambda a: a.mean(axis=2)  # noqa: E731
    diffs = [(f"random_walk - Mitsuba\n(relMSE {by['random_walk']['relmse_vs_mitsuba']:.1e}, "
              f"z pass {by['random_walk']['z_pass_fraction']:.3f})", lum(images["random_walk"] - mi)),
             (f"better_dipole - Mitsuba\n(relMSE {by['better_dipole']['relmse_vs_mitsuba']:.1e}, "
              f"z pass {by['better_dipole']['z_pass_fraction']:.3f})", lum(images["better_dipole"] - mi))]
    lim = max(float(np.percentile(np.abs(d), 99.5)) for _, d in diffs) or 1.0
    fig, axes = plt.subplots(1, 5, figsize=(13.5, 2.6))
    for ax, (lab, key) in zip(axes[:3], [(f"Mitsuba 3 volpath, {rows[0]['spp']} spp", "mitsuba"),
                                         (f"pellucid random_walk, {by['random_walk']['spp']} spp", "random_walk"),
                                         (f"pellucid better_dipole, {by['better_dipole']['spp']} spp", "better_dipole")]):
        ax.imshow(tonemap(images[key]), interpolation="nearest")
        ax.set_title(lab, fontsize=7)
    for ax, (lab, d) in zip(axes[3:], diffs):
        im = ax.imshow(d, cmap="RdBu_r", vmin=-lim, vmax=lim, interpolation="nearest")
        ax.set_title(lab, fontsize=7)
    fig.colorbar(im, ax=axes[3:].tolist(), fraction=0.03, label="mean of RGB difference")
    for ax in axes:
        ax.axis("off")
    fig.suptitle("bench/scenes/subsurface_sphere: sigma_t 20, albedo (0.9, 0.8, 0.7), g 0.3, eta 1.4", fontsize=8)
    fig.savefig(path, dpi=80, bbox_inches="tight")
    plt.close(fig)


# ------------------------------------------------------------------------------------- main
def choices_logged(scene: dict) -> List[str]:
    """The render log's model choice per object when the scene is built (logger "pellucid", INFO)."""
    import pellucid

    lines: List[str] = []

    class Grab(logging.Handler):
        def emit(self, record):
            if "subsurface model" in record.getMessage():
                lines.append(record.getMessage())

    lg = logging.getLogger("pellucid")
    h, old = Grab(level=logging.INFO), lg.level
    lg.addHandler(h)
    lg.setLevel(logging.INFO)
    try:
        pellucid.load_dict(scene, base_dir=SCENE.parent)
    finally:
        lg.removeHandler(h)
        lg.setLevel(old)
    return lines


def main(argv: Optional[Sequence[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ref-spp", type=int, default=512, help="the random-walk reference's spp")
    ap.add_argument("--max-spp", type=int, default=1024, help="the ladder's last rung")
    ap.add_argument("--rung-cap", type=float, default=20.0, help="stop a model's ladder after a rung this long (s)")
    ap.add_argument("--equal-time", type=float, default=4.0, help="the equal-time images' budget (s)")
    ap.add_argument("--mitsuba-spp", type=int, default=4096)
    ap.add_argument("--mitsuba-ours-spp", type=int, default=1024)
    ap.add_argument("--no-mitsuba", action="store_true")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out-dir", default=str(HERE / "results" / "subsurface"))
    ap.add_argument("--cache-dir", default=str(HERE / "cache"))
    args = ap.parse_args(argv)
    from pellucid.bench import machine_note

    t_start = time.perf_counter()
    load_before = machine_note()
    out = pathlib.Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    scene = json.loads(SCENE.read_text())
    choices = choices_logged(scene)
    for c in choices:
        log(c)
    ref, ref_var, ref_meta = reference(scene, args)
    from pellucid.bench import ref_relmse_floor

    ref_floor = ref_relmse_floor(ref, ref_var)
    log(f"reference noise floor (relMSE) {ref_floor:.3e}")
    rows = ladder(scene, ref, ref_floor, args)
    write_csv(out / "image_error_vs_time.csv", rows)
    plot_error(rows, ref_meta, out / "image_error_vs_time.png")

    sp = speedup(rows)
    if sp:
        write_csv(out / "auto_speedup.csv", sp)
    floors = {m: plateau(rows, m) for m in MODELS}
    last = {m: max((r for r in rows if r["model"] == m), key=lambda r: r["spp"]) for m in MODELS}
    md = ["# Auto against the random walk at equal error (scenes/subsurface.json)", "",
          "Written by `bench/subsurface_charts.py`; the data are in `image_error_vs_time.csv`.", "",
          f"Reference: `random_walk` at {ref_meta['spp']} spp, seed {ref_meta['seed']} ({ref_meta['seconds']:.0f} s); "
          f"its noise floor is relMSE {ref_floor:.2e}. Renders: {args.threads} threads, warm. Machine: {load_before} "
          "at the start.", "",
          "Auto's choices (the render log):", ""]
    for c in choices:
        line = c.split(": ", 1)[1]
        shape = line.split(" ", 1)[0]
        md.append(f"- {OBJECTS.get(shape, shape)}: {line}")
    md += ["", "| model | largest spp | seconds | relMSE | image noise | bias floor |", "|---|---|---|---|---|---|"]
    md += [f"| {m} | {last[m]['spp']} | {last[m]['seconds']:.2f} | {last[m]['relmse']:.3e} | "
           f"{last[m]['image_noise']:.2e} | {floors[m]:.2e} |" for m in MODELS]
    md += ["", "bias floor = relMSE at the largest spp less the image's own noise and the reference's floor "
           "(0 for the unbiased random walk up to noise).", ""]
    if sp:
        md += ["| relMSE level | auto [s] | random_walk [s] | speed-up |", "|---|---|---|---|"]
        md += [f"| {s['relmse']:.3e} | {s['auto_seconds']:.3f} | {s['random_walk_seconds']:.3f} | "
               f"{s['speedup']:.1f}x |" for s in sp]
        lo, hi = min(s["speedup"] for s in sp), max(s["speedup"] for s in sp)
        md += ["", f"**Auto reaches the same error {lo:.1f}x to {hi:.1f}x sooner than the random walk** at relMSE "
               f"{sp[-1]['relmse']:.2g} to {sp[0]['relmse']:.2g} (levels at least 3x auto's bias floor + the "
               f"reference floor, {floors['auto'] + ref_floor:.2e}; times interpolated in log-log between rungs).", ""]
    else:
        md += ["", "No error level lies above auto's bias floor within both ladders: no speed-up measured.", ""]
    (out / "auto_speedup.md").write_text("\n".join(md))

    tiles = equal_time(scene, ref, rows, args)
    tiles.append((f"reference: random_walk\n{ref_meta['spp']} spp", ref))
    plot_equal_time(tiles, out / "models_equal_time.png",
                    f"scenes/subsurface.json: each model for {args.equal_time:g} s ({args.threads} threads); "
                    "rows: full frame, slab + small sphere, torus")
    mi_rows = mitsuba(args, out)
    log(f"done in {time.perf_counter() - t_start:.0f} s; wrote {out}")
    for m in MODELS:
        log(f"  {m:14s} {last[m]['spp']:5d} spp relMSE {last[m]['relmse']:.3e}, bias floor {floors[m]:.2e}")
    for s in sp:
        log(f"  relMSE {s['relmse']:.3e}: auto {s['auto_seconds']:.2f} s, random walk "
            f"{s['random_walk_seconds']:.2f} s, speed-up {s['speedup']:.1f}x")
    for r in mi_rows or []:
        log(f"  {r['renderer']} {r['model']}: relMSE vs Mitsuba {r['relmse_vs_mitsuba']:.3e}, "
            f"z pass {r['z_pass_fraction']:.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Error-against-time charts for participating media: bench/results/media/<chart>.{csv,png}.
SPDX-License-Identifier: Apache-2.0

    .venv/bin/python bench/media_charts.py nee        # medium_nee on / off, scenes/fog.json
    .venv/bin/python bench/media_charts.py channels   # channel_sampling throughput / uniform, scenes/glass_medium.json
    .venv/bin/python bench/media_charts.py tracking   # ratio / delta tracking, scenes/smoke.json
    .venv/bin/python bench/media_charts.py mitsuba    # ours / Mitsuba 3 volpath (llvm_ad_rgb), two parity scenes
        [--size 128] [--spp 4,16,64,256] [--ref-spp 1024] [--threads 0] [--out-dir bench/results/media]

`python -m pellucid bench` varies only `integrator.strategy`; these charts vary other integrator and
medium options, so this script renders variants of one scene dict on a ladder of sample counts, times
each render (an untimed 1-spp warm-up first) and measures relMSE against a high-spp reference rendered
by pellucid with the scene's default options (every variant is unbiased, so they share it). The
metrics, the reference's noise floor and the chart style are pellucid.bench's.

The `mitsuba` chart renders tests/parity/scenes/medium_fog_box.xml and medium_glass_sphere.xml, which
pellucid loads too (`pellucid.load_file`), with both renderers in one run. Mitsuba runs in a subprocess
with the peer's own Python (bench/.venv-mitsuba, made by bench/peers/setup_mitsuba.sh); that process
imports bench/peers/mitsuba_runner.py for its Dr.Jit set-up and renders each spp once untimed (the
LLVM kernel bakes spp in) before the timed render, as the runner does.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time
from typing import Dict, List, Optional, Sequence

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
PARITY = ROOT / "tests" / "parity" / "scenes"


# ------------------------------------------------------------------------------ Mitsuba worker
def mitsuba_worker(xml: str, spps: Sequence[int], seed: int, threads: int, out: str) -> None:
    """Runs in the Mitsuba peer's Python (no pellucid): renders `xml` at every spp, saves an .npz."""
    sys.path.insert(0, str(HERE / "peers"))
    import mitsuba_runner  # noqa: F401  (sets up Dr.Jit's LLVM library before importing it)
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant("llvm_ad_rgb")
    mi.set_log_level(mi.LogLevel.Warn)
    res = {}
    for i, spp in enumerate(spps):
        scene = mi.load_file(xml)
        if threads > 0:
            dr.set_thread_count(threads)

        def render(s):
            img = mi.render(scene, spp=spp, seed=s)
            dr.eval(img)
            dr.sync_thread()
            return img

        render(seed + 1_000_003 + i)  # untimed: compiles the kernel this spp uses
        t0 = time.perf_counter()
        img = render(seed + 7919 * i)
        secs = time.perf_counter() - t0
        a = np.array(img, dtype=np.float32)[..., :3]
        res[f"img{i}"] = a
        res[f"sec{i}"] = np.float64(secs)
        res[f"nonfinite{i}"] = np.int64((~np.isfinite(a)).sum())
    np.savez(out, **res)


# ------------------------------------------------------------------------------ pellucid side
def _resized_xml(xml: pathlib.Path, size: int, tmp: pathlib.Path) -> pathlib.Path:
    """A copy of a parity scene with a size x size film, next to a link to its assets."""
    text = re.sub(r'(<integer name="(?:width|height)" value=")\d+(")', rf"\g<1>{size}\g<2>", xml.read_text())
    (tmp / "assets").symlink_to(xml.parent / "assets")
    out = tmp / xml.name
    out.write_text(text)
    return out


def _render(scene, spp: int, seed: int, threads: int):
    import numpy as np
    import pellucid

    pellucid.render_with_stats(scene, spp=1, seed=seed + 1_000_003, threads=threads)  # untimed warm-up
    img, var, st = pellucid.render_with_stats(scene, spp=spp, seed=seed, threads=threads)
    return np.array(img), np.array(var), st


def _variant(base: dict, integrator: Optional[dict] = None, medium: Optional[dict] = None) -> dict:
    d = json.loads(json.dumps(base))
    if integrator:
        d.setdefault("integrator", {"type": "path"}).update(integrator)
    if medium:
        for m in d["media"].values():
            m.update(medium)
    return d


CHARTS = {
    "nee": ("scenes/fog.json", "fog Cornell box (g = 0.7): next-event estimation at medium vertices",
            [("medium_nee on", {"medium_nee": True}, None), ("medium_nee off", {"medium_nee": False}, None)]),
    "channels": ("scenes/glass_medium.json", "glass sphere of milk (sigma_t = [6, 7, 9]): distance-sampling channel",
                 [("throughput", {"channel_sampling": "throughput"}, None),
                  ("uniform", {"channel_sampling": "uniform"}, None)]),
    "tracking": ("scenes/smoke.json", "smoke grid: shadow-ray transmittance estimator",
                 [("ratio tracking", None, {"tracking": "ratio"}), ("delta tracking", None, {"tracking": "delta"})]),
}
MITSUBA_SCENES = ("medium_fog_box", "medium_glass_sphere")


def _mitsuba_python() -> Optional[pathlib.Path]:
    from pellucid.bench import mitsuba_python
    return mitsuba_python()


def run_chart(chart: str, args) -> List[Dict]:
    import numpy as np
    import pellucid
    from pellucid.bench import ref_relmse_floor, rel_mse, rmse

    rows: List[Dict] = []
    if chart in CHARTS:
        rel, _, variants = CHARTS[chart]
        path = ROOT / rel
        base = json.loads(path.read_text())
        base["film"].update(width=args.size, height=args.size)
        ref_scene = pellucid.load_dict(base, base_dir=path.parent)
        cases = [(rel, label, lambda i=i, m=m: pellucid.load_dict(_variant(base, i, m), base_dir=path.parent))
                 for label, i, m in variants]
        refs = {rel: ref_scene}
    else:
        tmp = pathlib.Path(tempfile.mkdtemp(prefix="media_charts_"))
        cases, refs, xmls = [], {}, {}
        for name in MITSUBA_SCENES:
            (tmp / name).mkdir()
            xml = _resized_xml(PARITY / f"{name}.xml", args.size, tmp / name)
            xmls[name] = xml
            refs[name] = pellucid.load_file(xml)
            cases.append((name, "pellucid", lambda x=xml: pellucid.load_file(x)))
            cases.append((name, "mitsuba llvm_ad_rgb", None))
    references = {}
    for key, sc in refs.items():
        t0 = time.perf_counter()
        img, var, st = pellucid.render_with_stats(sc, spp=args.ref_spp, seed=args.seed + 555, threads=args.threads)
        references[key] = (np.array(img), np.array(var))
        print(f"{key}: reference {args.ref_spp} spp in {time.perf_counter() - t0:.1f} s, "
              f"invalid samples {st['invalid_samples']}", file=sys.stderr)
    for key, label, make in cases:
        ref, rvar = references[key]
        floor = ref_relmse_floor(ref, rvar)
        if make is None:  # Mitsuba
            py = _mitsuba_python()
            if py is None:
                print(f"{key}: Mitsuba 3 is not set up (bench/peers/setup_mitsuba.sh); skipped", file=sys.stderr)
                continue
            with tempfile.TemporaryDirectory() as td:
                out = pathlib.Path(td) / "m.npz"
                cmd = [str(py), str(pathlib.Path(__file__).resolve()), "--mitsuba-worker", str(xmls[key]),
                       "--spp", ",".join(map(str, args.spp)), "--seed", str(args.seed),
                       "--threads", str(args.threads), "--worker-out", str(out)]
                r = subprocess.run(cmd, capture_output=True, text=True)
                if r.returncode != 0:
                    raise RuntimeError(f"Mitsuba worker failed:\n{(r.stderr or r.stdout)[-3000:]}")
                z = np.load(out)
                results = [(z[f"img{i}"], float(z[f"sec{i}"]), int(z[f"nonfinite{i}"])) for i in range(len(args.spp))]
        else:
            sc = make()
            results = []
            for i, spp in enumerate(args.spp):
                img, _, st = _render(sc, spp, args.seed + 7919 * i, args.threads)
                results.append((img, float(st["seconds"]), int(st["invalid_samples"])))
        for spp, (img, secs, bad) in zip(args.spp, results):
            row = {"scene": key, "method": label, "spp": spp, "seconds": secs, "relmse": rel_mse(img, ref),
                   "rmse": rmse(img, ref), "ref_relmse_floor": floor, "invalid_samples": bad,
                   "nonfinite_pixels": int((~np.isfinite(img)).sum())}
            rows.append(row)
            print(f"{key:22s} {label:20s} {spp:5d} spp {secs:7.3f} s relMSE {row['relmse']:.4e} "
                  f"invalid {bad}", file=sys.stderr)
    return rows


def write(rows: List[Dict], chart: str, args, title: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = pathlib.Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    fields = ["scene", "method", "spp", "seconds", "relmse", "rmse", "ref_relmse_floor", "invalid_samples",
              "nonfinite_pixels"]
    with open(out / f"{chart}.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    fig, axes = plt.subplots(1, len(scenes), figsize=(5.2 * len(scenes), 4.2), squeeze=False)
    for ax, sc in zip(axes[0], scenes):
        for m in dict.fromkeys(r["method"] for r in rows if r["scene"] == sc):
            rr = [r for r in rows if r["scene"] == sc and r["method"] == m]
            ax.loglog([r["seconds"] for r in rr], [r["relmse"] for r in rr], "o-", label=m)
            for r in rr:
                ax.annotate(str(r["spp"]), (r["seconds"], r["relmse"]), fontsize=7, xytext=(3, 3),
                            textcoords="offset points")
        floor = next(r["ref_relmse_floor"] for r in rows if r["scene"] == sc)
        ax.axhline(floor, color="grey", ls=":", lw=1, label="reference noise floor")
        ax.set_xlabel("render time (s)")
        ax.set_ylabel("relMSE")
        ax.set_title(sc if len(scenes) > 1 else title, fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    if len(scenes) > 1:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(out / f"{chart}.png", dpi=90)
    plt.close(fig)


def main(argv: Optional[Sequence[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("chart", nargs="?", choices=[*CHARTS, "mitsuba"])
    ap.add_argument("--size", type=int, default=128, help="film width and height")
    ap.add_argument("--spp", default="4,16,64,256", help="the ladder of sample counts")
    ap.add_argument("--ref-spp", type=int, default=1024)
    ap.add_argument("--threads", type=int, default=0, help="0 = all cores")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out-dir", default=str(HERE / "results" / "media"))
    ap.add_argument("--mitsuba-worker", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--worker-out", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    args.spp = [int(s) for s in args.spp.split(",") if s.strip()]
    if args.mitsuba_worker:
        mitsuba_worker(args.mitsuba_worker, args.spp, args.seed, args.threads, args.worker_out)
        return 0
    if args.chart is None:
        ap.error("give a chart: " + ", ".join([*CHARTS, "mitsuba"]))
    t0 = time.perf_counter()
    rows = run_chart(args.chart, args)
    title = CHARTS[args.chart][1] if args.chart in CHARTS else "ours (path) vs Mitsuba 3 volpath (llvm_ad_rgb)"
    write(rows, args.chart, args, title)
    print(f"{args.chart}: {time.perf_counter() - t0:.0f} s in all; wrote {args.out_dir}/{args.chart}.{{csv,png}}",
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

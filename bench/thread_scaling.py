#!/usr/bin/env python3
"""Render time of every suite scene on 1 and on N threads, and the speed-up.

    python bench/thread_scaling.py [--threads 2] [--spp 64] [--scenes a,b]
        [--binary build/py/cpp/pellucid-render] [--out bench/results/suite/threads.md]

The time is the render's own (the line `pellucid-render` prints: "64 spp, 2.758 s, ..."), without
start-up and loading, each the median of --repeats runs.
"""
from __future__ import annotations

import argparse
import pathlib
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[1]


def render_seconds(binary: str, scene: pathlib.Path, spp: int, threads: int, out: pathlib.Path) -> float:
    r = subprocess.run([binary, str(scene), "--spp", str(spp), "--threads", str(threads), "-o", str(out)],
                       capture_output=True, text=True, cwd=scene.parent)
    if r.returncode != 0:
        raise RuntimeError(f"{scene.name}: {r.stderr[-2000:]}")
    m = re.search(r"(\d+) spp, ([0-9.]+) s,", r.stdout + r.stderr)
    if not m:
        raise RuntimeError(f"{scene.name}: no render time in the output")
    return float(m.group(2))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--scenes", default="")
    ap.add_argument("--binary", default=str(ROOT / "build" / "py" / "cpp" / "pellucid-render"))
    ap.add_argument("--out", default=str(ROOT / "bench" / "results" / "suite" / "threads.md"))
    args = ap.parse_args(argv)
    sys.path.insert(0, str(ROOT / "bench"))
    from profile_suite import suite_entries  # noqa: E402

    try:
        entries = suite_entries(args.scenes)
    except KeyError as e:
        print(f"thread_scaling: {e.args[0]}", file=sys.stderr)
        return 2
    rows = []
    with tempfile.TemporaryDirectory() as td:
        out = pathlib.Path(td) / "out.exr"
        for e in entries:
            scene = ROOT / "bench" / "suite" / e["file"]
            t1, tn = [], []
            for _ in range(args.repeats):  # alternated, so a drift in the machine's speed hits both
                t1.append(render_seconds(args.binary, scene, args.spp, 1, out))
                tn.append(render_seconds(args.binary, scene, args.spp, args.threads, out))
            a, b = statistics.median(t1), statistics.median(tn)
            rows.append((e["name"], a, b, a / b))
            print(f"{e['name']}: {a:.3f} s / {b:.3f} s = {a / b:.2f}x", file=sys.stderr)
    speedups = [r[3] for r in rows]
    geo = statistics.geometric_mean(speedups)
    lines = [
        f"# Render time on 1 and {args.threads} threads",
        "",
        f"`python bench/thread_scaling.py --threads {args.threads} --spp {args.spp} --repeats {args.repeats}`: "
        f"`pellucid-render SCENE --spp {args.spp} --threads T`, the render time it prints (no start-up or "
        f"loading), median of {args.repeats} alternated runs.",
        "",
        f"| scene | 1 thread (s) | {args.threads} threads (s) | speed-up |",
        "|---|---|---|---|",
    ]
    lines += [f"| {n} | {a:.3f} | {b:.3f} | {s:.2f}x |" for n, a, b, s in rows]
    lines += ["", f"Geometric mean {geo:.2f}x, lowest {min(speedups):.2f}x ({rows[speedups.index(min(speedups))][0]})."]
    pathlib.Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    pathlib.Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

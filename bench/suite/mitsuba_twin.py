#!/usr/bin/env python3
"""Render a suite scene's Mitsuba 3 XML twin (scenes with media, which bench/peers/mitsuba_runner.py
cannot convert from JSON). Same command line subset and JSON report as the runner:

    bench/.venv-mitsuba/bin/python bench/suite/mitsuba_twin.py SCENE.xml --spp N --width W --height H \
        --seed S --out OUT.exr [--passes K] [--threads T] [--json-report REPORT.json] [--each-dir DIR]

The twin takes `spp`, `width` and `height` as XML parameters. Importing the runner sets up Dr.Jit's
LLVM library; as the runner does, one untimed render with the timed configuration compiles the kernel
first. This script never imports pellucid.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "peers"))
import mitsuba_runner as runner  # noqa: E402  (sets DRJIT_LIBLLVM_PATH before drjit is imported)

dr, mi, np = runner.dr, runner.mi, runner.np


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--variant", choices=["scalar_rgb", "llvm_ad_rgb"], default="llvm_ad_rgb")
    ap.add_argument("--spp", type=int, required=True)
    ap.add_argument("--width", type=int, required=True)
    ap.add_argument("--height", type=int, required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", required=True)
    ap.add_argument("--passes", type=int, default=1)
    ap.add_argument("--threads", type=int, default=0, help="0: all cores")
    ap.add_argument("--json-report", default=None)
    ap.add_argument("--each-dir", default=None, help="also write each pass's image as EACH_DIR/<k>.exr")
    a = ap.parse_args(argv)
    K = a.passes
    if K < 1 or a.spp < 1 or a.spp % K:
        ap.error("--spp must be a positive multiple of --passes")
    spp_pass = a.spp // K
    mi.set_variant(a.variant)
    mi.set_log_level(mi.LogLevel.Warn)
    t0 = time.perf_counter()
    scene = mi.load_file(a.scene, spp=str(spp_pass), width=str(a.width), height=str(a.height))
    load_s = time.perf_counter() - t0
    if a.threads > 0:  # after loading, as the runner does (EXR I/O on a one-thread pool deadlocks)
        dr.set_thread_count(a.threads)
    if a.variant.startswith("llvm"):
        runner._render(scene, spp_pass, a.seed + 1_000_003)  # untimed: compiles the timed kernel
    imgs, secs = [], []
    for s in ([a.seed] if K == 1 else [a.seed * K + k for k in range(K)]):
        t0 = time.perf_counter()
        img = runner._render(scene, spp_pass, s)
        secs.append(time.perf_counter() - t0)
        imgs.append(np.array(img, dtype=np.float64)[..., :3])
    if int(dr.thread_count()) < 2:
        dr.set_thread_count(2)
    stack = np.stack(imgs)
    runner._write_exr(a.out, stack.mean(axis=0))
    if K > 1:
        runner._write_exr(os.path.splitext(a.out)[0] + ".var.exr", stack.var(axis=0, ddof=1) / K)
    if a.each_dir:
        os.makedirs(a.each_dir, exist_ok=True)
        for k, im in enumerate(imgs):
            runner._write_exr(os.path.join(a.each_dir, f"{k}.exr"), im)
    if a.json_report:
        with open(a.json_report, "w") as f:
            json.dump({"variant": a.variant, "spp": a.spp, "passes": K, "width": a.width, "height": a.height,
                       "seconds": float(sum(secs)), "load_seconds": load_s, "peak_rss_mb": runner._peak_rss_mb(),
                       "nonfinite": int((~np.isfinite(stack)).sum())}, f)
    return 0


if __name__ == "__main__":
    sys.exit(main())

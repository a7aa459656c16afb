"""Command line: ``python -m pellucid render SCENE -o OUT [--spp N] [--seed S] [--threads T] [--sampler S]``
and ``python -m pellucid bench ...`` (the benchmarks of ``pellucid.bench``).

``render`` takes the same flags as the C++ ``pellucid-render`` and gives the same image for the
same seed.
"""
from __future__ import annotations

import argparse
import importlib
import logging
import sys
import threading
from typing import List, Optional

import pellucid


def _build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="pellucid", description="pellucid physically based renderer")
    p.add_argument("--version", action="version", version=f"pellucid {pellucid.__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("render", help="render a scene file")
    r.add_argument("scene", help="scene file (.json)")
    r.add_argument("-o", "--output", action="append", required=True,
                   help="output image (.exr keeps HDR; .png/.jpg tone-mapped sRGB); repeatable")
    r.add_argument("--spp", type=int, default=None, help="samples per pixel (default: the scene's)")
    r.add_argument("--seed", type=int, default=None, help="random seed (default: the scene's)")
    r.add_argument("--threads", type=int, default=0, help="worker threads (0 = all cores)")
    r.add_argument("--sampler", choices=list(pellucid.SAMPLERS), default=None,
                   help="override the scene's sampler type (sobol: Owen-scrambled Sobol, lower error at equal spp)")
    r.add_argument("--aov", choices=list(pellucid.AOVS), default=None,
                   help="render this AOV of the first hit instead of the scene's integrator (as pellucid-render --aov)")
    r.add_argument("--time-budget", type=float, default=None, help="stop after about this many seconds")
    r.add_argument("--lenient", action="store_true",
                   help="Mitsuba XML: unsupported elements are warnings (skipped), not errors")
    r.add_argument("-q", "--quiet", action="store_true", help="no progress bar or summary")
    sub.add_parser("bench", add_help=False, help="benchmarks (pellucid.bench); `bench --help` for its options")
    return p


def _bench(argv: List[str]) -> int:
    """Hand the arguments after ``bench`` to pellucid.bench.main, imported only now (it pulls in
    plotting and peer-renderer code that rendering does not need)."""
    try:
        bench = importlib.import_module("pellucid.bench")
    except ImportError as e:
        print(f"pellucid: error: the bench subcommand is not available: cannot import pellucid.bench ({e})",
              file=sys.stderr)
        return 2
    rc = bench.main(argv)
    return int(rc) if rc is not None else 0


def _render(args: argparse.Namespace) -> int:
    if args.spp is not None and not (1 <= args.spp <= 1 << 24):
        raise pellucid.Error(f"--spp: value {args.spp} must be in [1, 16777216]")
    if args.seed is not None and args.seed < 0:
        raise pellucid.Error("--seed: value must be >= 0")
    if not (0 <= args.threads <= 4096):
        raise pellucid.Error("--threads: value must be in [0, 4096]")
    scene = pellucid.load_file(args.scene, lenient=args.lenient)
    if args.aov is not None:
        image = pellucid.render_aov(scene, args.aov, spp=args.spp, seed=args.seed, threads=args.threads)
        for out in args.output:
            pellucid.write_image(out, image)
            if not args.quiet:
                print(f"wrote {out}", file=sys.stderr)
        return 0
    result = {}

    def work() -> None:
        try:
            result["out"] = pellucid.render_with_stats(
                scene, spp=args.spp, seed=args.seed, threads=args.threads,
                time_budget=args.time_budget, sampler=args.sampler, progress=not args.quiet and sys.stderr.isatty())
        except BaseException as e:  # re-raised in the main thread
            result["error"] = e

    # Render in a worker so that Ctrl-C reaches the main thread, which then asks the core to stop;
    # the samples finished so far are still written.
    t = threading.Thread(target=work, daemon=True)
    t.start()
    try:
        while t.is_alive():
            t.join(0.1)
    except KeyboardInterrupt:
        pellucid.cancel()
        t.join()
    if "error" in result:
        raise result["error"]
    image, _, stats = result["out"]
    for out in args.output:
        pellucid.write_image(out, image)
        if not args.quiet:
            print(f"wrote {out}", file=sys.stderr)
    if stats["invalid_samples"]:
        print(f"pellucid: warning: {stats['invalid_samples']} NaN/Inf/negative samples were discarded",
              file=sys.stderr)
    if not args.quiet:
        rate = stats["samples"] / max(stats["seconds"], 1e-9) * 1e-6
        print(f"{stats['spp']} spp, {stats['seconds']:.3f} s, {rate:.3f} M samples/s", file=sys.stderr)
    if stats["cancelled"]:
        print("pellucid: interrupted; the image holds the samples finished so far", file=sys.stderr)
        return 130
    return 0


class _LogFormat(logging.Formatter):
    def format(self, record: logging.LogRecord) -> str:
        return f"pellucid: {record.levelname.lower()}: {record.getMessage()}"


def _setup_logging() -> None:
    """Warnings of the renderer (logger "pellucid") go to stderr, unless the caller configured
    logging already."""
    log = logging.getLogger("pellucid")
    if log.handlers or logging.getLogger().handlers:
        return
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(_LogFormat())
    handler.setLevel(logging.WARNING)
    log.addHandler(handler)


def main(argv: Optional[List[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    _setup_logging()
    if argv[:1] == ["bench"]:
        return _bench(argv[1:])
    args = _build_parser().parse_args(argv)
    try:
        if args.command == "render":
            return _render(args)
    except pellucid.Error as e:
        print(f"pellucid: error: {e}", file=sys.stderr)
        return 1
    return 2


if __name__ == "__main__":
    sys.exit(main())

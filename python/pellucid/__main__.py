"""Command line: ``python -m pellucid render SCENE -o OUT [--spp N] [--seed S] [--threads T] [--sampler S]
[--aovs albedo,normal,...] [-D NAME=VALUE] [--resume STATE] [--state STATE] ...``, ``python -m pellucid bench ...``
(the benchmarks of ``pellucid.bench``) and ``python -m pellucid stability [--quick] [--json FILE]`` (the
NaN/Inf/negative sweep of ``pellucid.stability``).

``render`` takes the same flags as the C++ ``pellucid-render``, prints the same help and errors, and
gives the same image for the same seed. SIGINT (Ctrl-C) or SIGTERM stops it within about a second:
the complete passes are written, with the film state to ``--resume`` from (docs/rendering.md).
"""
from __future__ import annotations

import argparse
import importlib
import logging
import os
import signal
import sys
from typing import Dict, List, Optional

import pellucid


def _int_in(lo: int, hi: Optional[int]):
    """An argparse type: an integer in [lo, hi] (hi None: no upper bound), worded as pellucid-render."""
    def parse(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"invalid int value '{text}'") from None
        if v < lo or (hi is not None and v > hi):
            raise argparse.ArgumentTypeError(f"value {text} must be >= {lo}" if hi is None
                                             else f"value {text} must be in [{lo}, {hi}]")
        return v
    return parse


def _seconds(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid value '{text}'") from None
    if not v > 0:
        raise argparse.ArgumentTypeError(f"value {text} must be > 0")
    return v


def _aov_list(text: str) -> List[str]:
    """An argparse type: a comma-separated list of AOV names, worded as pellucid-render."""
    try:
        return pellucid.aov.parse_aovs(text)
    except pellucid.Error as e:
        raise argparse.ArgumentTypeError(str(e).split(": ", 1)[1]) from None


def _is_exr(path: str) -> bool:
    return os.fspath(path).lower().endswith(".exr")


def _build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="pellucid", description="pellucid physically based renderer")
    p.add_argument("--version", action="version", version=f"pellucid {pellucid.__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    # The same options, metavars and help texts as pellucid-render (cpp/app/main.cpp).
    r = sub.add_parser("render", help="render a scene file", description="render a scene file")
    r.add_argument("scene", help="scene file (.json or Mitsuba 3 .xml)")
    r.add_argument("-o", "--output", action="append", required=True, metavar="OUTPUT",
                   help="output image (.exr keeps HDR; .png/.jpg tone-mapped sRGB); repeatable; missing folders "
                        "are created")
    r.add_argument("--spp", type=_int_in(1, 1 << 24), default=None, metavar="SPP", help="samples per pixel (default: the scene's)")
    r.add_argument("--seed", type=_int_in(0, None), default=None, metavar="SEED", help="random seed (default: the scene's)")
    r.add_argument("--threads", type=_int_in(0, 4096), default=0, metavar="THREADS", help="worker threads (0 = all cores)")
    r.add_argument("--sampler", choices=list(pellucid.SAMPLERS), default=None,
                   help="override the scene's sampler type (sobol: Owen-scrambled Sobol, lower error at equal spp)")
    r.add_argument("--aov", choices=list(pellucid.aov.SINGLE_AOVS), default=None,
                   help="render this AOV of the first hit instead of the scene's integrator (as pellucid-render --aov)")
    r.add_argument("--aovs", type=_aov_list, default=None, metavar="AOVS",
                   help=f"also render these AOVs (comma-separated: {', '.join(pellucid.AOVS)}), written as layers of "
                        "every .exr OUTPUT (as pellucid-render --aovs)")
    r.add_argument("--time-budget", type=_seconds, default=None, metavar="TIME_BUDGET",
                   help="stop after about this many seconds")
    r.add_argument("-D", "--define", action="append", default=[], metavar="NAME=VALUE",
                   help="set the Mitsuba XML parameter $NAME, overriding its <default> (repeatable)")
    r.add_argument("--resume", default=None, metavar="STATE",
                   help="continue the render saved in this film state file up to --spp (same scene, seed and sampler)")
    r.add_argument("--state", default=None, metavar="STATE",
                   help="write the film state here when the render stops (default on interruption: first OUTPUT + "
                        ".state)")
    r.add_argument("--lenient", action="store_true",
                   help="Mitsuba XML: unsupported elements are warnings (skipped), not errors")
    r.add_argument("-q", "--quiet", action="store_true", help="no progress bar or summary")
    sub.add_parser("bench", add_help=False, help="benchmarks (pellucid.bench); `bench --help` for its options")
    sub.add_parser("stability", add_help=False,
                   help="NaN/Inf/negative/dropped-sample sweep of every model (pellucid.stability); `stability --help`")
    return p


class _Terminated(KeyboardInterrupt):
    """Raised by the SIGTERM handler: stops a render like Ctrl-C (exit status 143 instead of 130)."""


def _on_sigterm(signum: int, frame: object) -> None:
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # a second SIGTERM ends the process at once
    raise _Terminated()


def _defines(items: List[str]) -> Dict[str, str]:
    out: Dict[str, str] = {}
    for d in items:
        name, eq, value = d.partition("=")
        if not eq or not name:
            raise pellucid.Error(f"-D: expected NAME=VALUE, got {d!r}")
        out[name] = value
    return out


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


def _stability(argv: List[str]) -> int:
    """``stability [--quick] [--json FILE] ...``: the sweep of pellucid.stability; exit status 1 when
    it counts any NaN, Inf, negative or dropped value."""
    stability = importlib.import_module("pellucid.stability")
    args = stability.build_parser(argparse.ArgumentParser(
        prog="pellucid stability", description=stability.__doc__.splitlines()[0])).parse_args(argv)
    return int(stability.main(args))


def _render(args: argparse.Namespace) -> int:
    params = _defines(args.define)
    # Everything that can fail before rendering does: outputs, the state file, the scene.
    for out in args.output:
        pellucid._core.check_image_output(os.fspath(out))
    if args.aovs and not any(_is_exr(out) for out in args.output):
        raise pellucid.Error("--aovs: AOVs are written as layers of a multi-layer EXR: give an .exr OUTPUT")
    resume = pellucid.load_film_state(args.resume) if args.resume else None
    scene = pellucid.load_file(args.scene, lenient=args.lenient, **params)
    # As pellucid-render: the film keeps each pixel's variance only for the variance AOV.
    kwargs = pellucid._render_kwargs(scene, args.spp, args.seed, args.threads, args.time_budget, None, args.sampler,
                                     resume, "variance" in (args.aovs or []))
    kwargs.update(keep_state=True, aov=args.aov or "", aovs=args.aovs or [])
    # As pellucid-render: SIGINT and SIGTERM stop the render even where the shell started us with
    # SIGINT ignored (a background job).
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, _on_sigterm)
    interrupted: Optional[KeyboardInterrupt] = None
    try:
        image, _, stats = pellucid._render_full(kwargs, progress=not args.quiet and sys.stderr.isatty())
    except KeyboardInterrupt as e:
        if not isinstance(getattr(e, "partial", None), pellucid.RenderOutput):
            raise
        interrupted = e
        image, stats = e.partial.image, e.partial.stats
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
    rc = 0 if interrupted is None else 143 if isinstance(interrupted, _Terminated) else 130
    if stats["spp"] == 0:
        print("pellucid: interrupted before the first pass finished; nothing written", file=sys.stderr)
        return rc
    aovs = stats.pop("aovs", None)
    if aovs is not None and not args.quiet:
        print(f"AOVs: {stats['aov_seconds']:.3f} s", file=sys.stderr)
    attributes = pellucid._render_attributes(stats)
    for out in args.output:
        if aovs is not None and _is_exr(out):
            pellucid.write_layers(out, image, aovs, attributes)
        else:
            pellucid.write_image(out, image, attributes)
        if not args.quiet:
            print(f"wrote {out}", file=sys.stderr)
    state_path = args.state or (args.output[0] + ".state" if interrupted is not None else None)
    if state_path:
        stats["state"].save(state_path)
        if not args.quiet or interrupted is not None:
            print(f"wrote film state {state_path}", file=sys.stderr)
    if stats["invalid_samples"]:
        print(f"pellucid: warning: {stats['invalid_samples']} NaN/Inf/negative samples were discarded",
              file=sys.stderr)
    if not args.quiet:
        rate = stats["samples"] / max(stats["seconds"], 1e-9) * 1e-6
        print(f"{stats['spp']} spp, {stats['seconds']:.3f} s, {rate:.3f} M samples/s, "
              f"{stats['invalid_samples']} invalid samples dropped", file=sys.stderr)
    if interrupted is not None:
        print(f"pellucid: interrupted at {stats['spp']} spp; the image holds the complete passes "
              f"(continue with --resume {state_path})", file=sys.stderr)
    return rc


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
    if argv[:1] == ["stability"]:
        try:
            return _stability(argv[1:])
        except pellucid.Error as e:
            print(f"pellucid: error: {e}", file=sys.stderr)
            return 2
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

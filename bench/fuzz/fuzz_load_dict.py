"""A mutation fuzzer for pellucid.load_dict (the Python entry point of the scene builder).

Starts from the JSON seed scenes (bench/fuzz/corpus/json), mutates one to three places of a copy
per run (values replaced by numbers at and past the float and integer limits, NaN, infinities,
wrong types, non-UTF-8 text, deep nesting, a reference to the dict itself; keys added or
deleted) and calls load_dict, then renders 1 spp when the film is small. The only acceptable
failure is pellucid.Error: any other exception is a crash, written to the crashes directory with
its traceback. Run i's input is a function of (--seed, i) alone; the number of the run in progress
is kept in <crashes>/last-run.txt (rewritten in place, no new file per run), so a run that takes the
process down can be rebuilt with --replay.

    python bench/fuzz/fuzz_load_dict.py --seconds 60 --crashes build/fuzz/crashes/load_dict
    python bench/fuzz/fuzz_load_dict.py --seconds 0 --runs 1000000 --crashes build/fuzz/crashes/load_dict
    python bench/fuzz/fuzz_load_dict.py --replay 123456     # print run 123456's input, then run it
"""
from __future__ import annotations

import argparse
import copy
import json
import logging
import os
import random
import sys
import time
import traceback
from pathlib import Path

import pellucid

HERE = Path(__file__).resolve().parent

ODD_VALUES = [
    0, -0.0, 1, -1, 0.5, -0.5, 2, 1e-320, 1e-45, 3.4e38, 3.5e38, 1e39, -1e39, 1e308, -1e308,
    float("nan"), float("inf"), float("-inf"), 2**31 - 1, 2**31, -2**31 - 1, 2**53 + 1, 2**63, 2**64,
    10**400, True, False, None, "", "x", "\udcff", "\x00", "é" * 3, "ggx", "Au", "bk7", "tex.png",
    "mesh.ply", "../mesh.obj", [], {}, [0, 0, 0], [1e39, 0, 0], [float("nan")] * 3, [0] * 16,
    [[0, 0, 0]], {"type": "image"}, {"type": "checkerboard", "color1": -5},
    {"type": "scale", "texture": 1, "scale": 1e38}, {"type": "mix"}, {"type": 3},
]


def deep_list(depth: int) -> list:
    v: list = []
    for _ in range(depth):
        v = [v]
    return v


def paths(obj, depth=0, seen=None):
    """Every (container, key) pair of the nested dicts and lists, to depth 12, each container once."""
    seen = set() if seen is None else seen
    if depth > 12 or id(obj) in seen:
        return
    if isinstance(obj, dict):
        seen.add(id(obj))
        for k in list(obj):
            yield obj, k
            yield from paths(obj[k], depth + 1, seen)
    elif isinstance(obj, list):
        seen.add(id(obj))
        for i in range(len(obj)):
            yield obj, i
            yield from paths(obj[i], depth + 1, seen)


def mutate(root: dict, rng: random.Random) -> None:
    spots = list(paths(root))
    if not spots:
        return
    parent, key = rng.choice(spots)
    r = rng.random()
    if r < 0.55:
        parent[key] = copy.deepcopy(rng.choice(ODD_VALUES))
    elif r < 0.65:
        v = parent[key]
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            parent[key] = v * rng.choice([-1, 1e10, 1e-10, 1e30, 3, 0.5]) + rng.choice([0, 1, -1])
        else:
            parent[key] = rng.choice(ODD_VALUES)
    elif r < 0.72:
        if isinstance(parent, dict):
            del parent[key]
        else:
            parent.pop(key)
    elif r < 0.80:
        if isinstance(parent, dict):
            parent[rng.choice(["type", "filename", "extra", "material", "emitter", "to_world"])] = rng.choice(ODD_VALUES)
        else:
            parent.append(copy.deepcopy(rng.choice(ODD_VALUES)))
    elif r < 0.87:
        parent[key] = deep_list(rng.choice([10, 300, 5000]))
    elif r < 0.92:
        parent[key] = root  # a dict that contains itself
    else:
        other = rng.choice(spots)
        parent[key] = copy.deepcopy(other[0][other[1]]) if other[0] is not parent else parent[key]


def short_repr(d) -> str:
    """repr (which shows a self-reference as {...}), with deep lists cut short."""
    try:
        text = repr(d)
    except RecursionError:
        text = "<too deep for repr>"
    return text if len(text) < 100_000 else text[:100_000] + "..."


def make_input(seeds: list, seed: int, run: int):
    """Run ``run``'s input: a mutated copy of a seed scene, or None when mutating it failed in Python
    itself (copying a deep list, scaling a huge int: not pellucid's)."""
    rng = random.Random(f"{seed}:{run}")
    d = copy.deepcopy(rng.choice(seeds))
    try:
        for _ in range(rng.randint(1, 3)):
            mutate(d, rng)
    except (RecursionError, OverflowError):
        return None
    return d


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=60, help="stop after this long (default 60; 0: no limit)")
    ap.add_argument("--runs", type=int, default=0, help="stop after this many executions (0: no limit)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--first-run", type=int, default=0, help="number of the first run (to continue a campaign)")
    ap.add_argument("--crashes", type=Path, default=Path("fuzz-crashes"))
    ap.add_argument("--replay", type=int, default=None, metavar="RUN", help="print run RUN's input and run it")
    args = ap.parse_args()
    # Warnings (of the renderer and of dropped samples) are expected for most inputs; printing them
    # would dominate the run time.
    logging.getLogger("pellucid").setLevel(logging.ERROR)
    seeds = [json.loads(p.read_text()) for p in sorted((HERE / "corpus" / "json").glob("*.json"))]
    assets = str(HERE / "assets")
    if args.replay is not None:
        d = make_input(seeds, args.seed, args.replay)
        print(short_repr(d))
        try:
            if d is not None:
                scene = pellucid.load_dict(d, base_dir=assets)
                pellucid.render(scene, spp=1, threads=1)
        except pellucid.Error as e:
            print(f"pellucid.Error: {e}")
        return 0
    args.crashes.mkdir(parents=True, exist_ok=True)
    last = os.open(args.crashes / "last-run.txt", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    pellucid_errors = renders = dropped = crashes = 0
    runs = 0
    run = args.first_run - 1
    t0 = time.monotonic()
    while (not args.runs or runs < args.runs) and (args.seconds <= 0 or time.monotonic() - t0 < args.seconds):
        run += 1
        d = make_input(seeds, args.seed, run)
        if d is None:
            continue
        os.pwrite(last, b"%-20d\n" % run, 0)  # survives a crash of the process
        runs += 1
        try:
            scene = pellucid.load_dict(d, base_dir=assets)
            if scene.width * scene.height <= 16 * 16:
                _, _, stats = pellucid.render_with_stats(scene, spp=1, threads=1)
                renders += 1
                dropped += stats["invalid_samples"]
        except pellucid.Error:
            pellucid_errors += 1
        except Exception:  # noqa: BLE001 - every other exception is what we look for
            crashes += 1
            out = args.crashes / f"crash-{run}.txt"
            out.write_text(short_repr(d) + "\n\n" + traceback.format_exc(), errors="backslashreplace")
            print(f"crash: {out} (--seed {args.seed} --replay {run})", file=sys.stderr)
    os.close(last)
    (args.crashes / "last-run.txt").unlink(missing_ok=True)
    dt = time.monotonic() - t0
    print(f"{runs} executions in {dt:.0f} s ({runs / dt:.0f} exec/s), {pellucid_errors} pellucid.Error, "
          f"{renders} renders ({dropped} dropped samples), {crashes} crashes")
    return 1 if crashes else 0


if __name__ == "__main__":
    sys.exit(main())

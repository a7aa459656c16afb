"""Time parameter updates (pellucid.parameters) against a full reload of the scene.

Usage (from the repository root; the suite's mesh is generated once with
``python bench/suite/make_suite.py --assets``)::

    python bench/parameter_update.py [--scene bench/suite/big_mesh.json] [--repeats 7]

Prints a Markdown table: the median wall time of each kind of update and of load_file.
"""
from __future__ import annotations

import argparse
import pathlib
import statistics
import sys
import time
from typing import Any, Callable, Dict, List

import pellucid

ROOT = pathlib.Path(__file__).resolve().parent.parent


def median_seconds(fn: Callable[[int], Any], repeats: int) -> float:
    times: List[float] = []
    for i in range(repeats):
        t0 = time.perf_counter()
        fn(i)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main(argv: List[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default=str(ROOT / "bench" / "suite" / "big_mesh.json"))
    ap.add_argument("--repeats", type=int, default=7)
    a = ap.parse_args(argv)
    path = pathlib.Path(a.scene)
    scene = pellucid.load_file(path)
    params = pellucid.parameters(scene)
    print(f"{path.name}: {pellucid.Scene.__name__} with {len(params)} parameters; {a.repeats} repeats, median")

    def update(values: Callable[[int], Dict[str, Any]]) -> Callable[[int], Any]:
        return lambda i: params.update(values(i))

    def translate(shape: int) -> Callable[[int], Dict[str, Any]]:
        base = params[f"shapes[{shape}].to_world"]
        return lambda i: {f"shapes[{shape}].to_world": base + [{"translate": [0, 0.001 * (i + 1), 0]}]}

    rows = [
        ("material (materials.gold.alpha)", update(lambda i: {"materials.gold.alpha": 0.1 + 0.05 * i})),
        ("light (lights[1].radiance)", update(lambda i: {"lights[1].radiance": 0.2 + 0.01 * i})),
        ("camera (camera.fov)", update(lambda i: {"camera.fov": 40 + i})),
        ("geometry: the ground rectangle moves (BVH rebuilt, mesh kept)", update(translate(0))),
        ("geometry: the 1M-triangle mesh moves (mesh read again)", update(translate(1))),
        ("full reload (load_file)", lambda i: pellucid.load_file(path)),
    ]
    builds = scene.bvh_builds
    print("| change | median seconds |\n|---|---|")
    for name, fn in rows:
        print(f"| {name} | {median_seconds(fn, a.repeats):.4f} |", flush=True)
    print(f"BVH builds during the geometry rows: {scene.bvh_builds - builds}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

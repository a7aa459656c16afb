#!/usr/bin/env python3
"""Where each suite scene's render time goes: `perf record` of `pellucid-render` on one thread, the
samples grouped by stage.

    python bench/profile_suite.py [--scenes a,b] [--spp 16] [--binary build/py/cpp/pellucid-render]
        [--out bench/results/suite/profile.md]

Needs Linux `perf` (linux-perf) with access to the CPU's cycle counter or, failing that, its
software clock. Every scene of bench/suite/suite.json is rendered once at --spp samples per pixel
on one thread (`--threads 1`, so the figures are per-core work), and once more at 1 spp. Samples are
grouped by symbol and shared object into the stages below, and each stage's samples in the 1-spp run
are subtracted from the full run's: what is left is the render of the other spp - 1 samples per pixel,
whatever code start-up and loading share with it (the rough coat tables a plastic integrates at load
call the same microfacet functions as one-lane BSDFs do at render time). Process start-up and scene
loading (the dynamic linker, the kernel's page faults, parsing, mesh reading, Embree's BVH build)
form their own group, reported as a share of the full run's process.
"""
from __future__ import annotations

import argparse
import json
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
from typing import Dict, List, Tuple

ROOT = pathlib.Path(__file__).resolve().parents[1]

# (stage, predicate on (shared object, symbol)), first match wins. The order matters: Embree's
# builders are loading, its other symbols traversal.
STAGES: List[Tuple[str, str, str]] = [
    # name, regex on the shared object, regex on the symbol
    # Every shared object but ours, Embree, OpenImageIO, libm and TBB only runs at start-up, loading
    # or writing the image (the dynamic linker, the kernel's page faults, image-format libraries).
    ("loading", r"^(?!pellucid|libembree|libOpenImageIO|libm\.so|libtbb)", r""),
    ("loading", r"libembree", r"(?i)build|morton|split|heuristic|bvh.*builder|refit|createLeaf|rtcCommit|parallel_"),
    ("loading", r"", r"(?i)json|mesh_io|load_|read_|parse|tinyobj|pugi|Mesh::|build_scene|scene_from|build\(|"
                         r"integrate_unit_square|interface_energy|coat_table"),
    ("ray traversal (Embree or direct)", r"libembree", r""),
    # Our spheres' intersection callbacks, which Embree's traversal calls (geometry/embree_scene.cpp),
    # and the direct trace of small scenes (geometry/direct_trace.cpp).
    ("ray traversal (Embree or direct)", r"", r"sphere_intersect|sphere_occluded|sphere_first_root|direct_trace::"),
    ("textures", r"OpenImageIO|libOpenImageIO", r""),
    ("textures", r"", r"(?i)texture|bump|perturbed_shading_frame|normal_map|lane_bilinear"),
    ("film", r"", r"Film::|film_add|FilmSample|filter_taps|gaussian_taps|accumulate_(avx2|any|baseline)"),
    ("camera rays, samplers", r"", r"path_services::start|Camera|Sampler|PCG32|sobol|sample_filter|truncated_gaussian|film_position|pixel_seed"),
    ("hit records", r"", r"fill_hit|fill_packet|fill_triangle|intersect_packet|occluded_packet|Interaction|compute_footprint|"
                         r"uv_differentials|approximate_dp_dxy|Scene::intersect|Scene::occluded|path_services::trace|"
                         r"hit_vertices|fetch_hit_vertex|EmbreeScene::intersect|EmbreeScene::occluded|"
                         r"path_services::occluded|next_ray|spawn_ray"),
    ("media, subsurface", r"", r"(?i)medium|phase|bssrdf|subsurface|searchlight|grid"),
    ("lights, emission", r"", r"(?i)light|escaped|emitted|envmap|emitter|infinite_hit|square_to_uniform_sphere"),
    # A packet form the compiler left out of line (its symbol names the SIMD batch) is packet code.
    ("packet kernel (packet BSDFs, MIS, roulette, bookkeeping)", r"", r"xsimd::batch"),
    ("BSDFs one lane at a time", r"", r"(?i)bsdf|bxdf|microfacet|beckmann|ggx|plastic|dielectric|conductor|principled|"
                                      r"fresnel|erfinv|lambert|oren|kulla|coat|sheen|disney|path_services::randoms"),
    ("packet kernel (packet BSDFs, MIS, roulette, bookkeeping)", r"", r"render_tile_kernel"),
    ("maths library (libm)", r"libm\.so", r""),
]


def classify(dso: str, sym: str) -> str:
    for name, dso_re, sym_re in STAGES:
        if dso_re and not re.search(dso_re, dso):
            continue
        if sym_re and not re.search(sym_re, sym):
            continue
        return name
    return "other"


def profile(binary: str, scene: pathlib.Path, spp: int, tmp: pathlib.Path) -> Dict[str, float]:
    data = tmp / "perf.data"
    cmd = ["perf", "record", "-q", "-F", "10000", "-o", str(data), binary, str(scene), "--spp", str(spp),
           "--threads", "1", "-o", str(tmp / "out.exr"), "--quiet"]
    r = subprocess.run(cmd, capture_output=True, text=True, cwd=scene.parent)
    if r.returncode != 0:
        raise RuntimeError(f"perf record failed on {scene.name}: {r.stderr[-2000:]}")
    rep = subprocess.run(["perf", "report", "-i", str(data), "--no-children", "--sort", "dso,sym", "--stdio", "-n",
                          "--percent-limit", "0"], capture_output=True, text=True)
    counts: Dict[str, float] = {}
    for line in rep.stdout.splitlines():
        m = re.match(r"\s*[0-9.]+%\s+([0-9]+)\s+(\S+)\s+\[[.k]\]\s+(.*)$", line)
        if not m:
            continue
        n, dso, sym = float(m.group(1)), m.group(2), m.group(3).strip()
        stage = classify(dso, sym)
        counts[stage] = counts.get(stage, 0.0) + n
    return counts


def suite_entries(scenes: str) -> List[dict]:
    """The manifest entries of bench/suite/suite.json named in `scenes` (comma-separated; "" = all),
    with their generated assets written into the cache (the big mesh). KeyError names unknown ones."""
    entries = json.loads((ROOT / "bench" / "suite" / "suite.json").read_text())["scenes"]
    names = [e["name"] for e in entries]
    if scenes:
        wanted = scenes.split(",")
        unknown = [w for w in wanted if w not in names]
        if unknown:
            raise KeyError(f"unknown scene(s) {unknown} (known: {', '.join(names)})")
        entries = [e for e in entries if e["name"] in wanted]
    sys.path.insert(0, str(ROOT / "bench" / "suite"))
    import make_suite  # noqa: E402

    make_suite.ensure_assets(sorted({a for e in entries for a in e.get("assets", [])}), log=lambda *a: None)
    return entries


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes", default="", help="comma-separated scene names (default: the whole suite)")
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--binary", default=str(ROOT / "build" / "py" / "cpp" / "pellucid-render"))
    ap.add_argument("--out", default=str(ROOT / "bench" / "results" / "suite" / "profile.md"))
    args = ap.parse_args(argv)
    if args.spp < 2:
        print("profile_suite: --spp must be at least 2 (the 1-spp run is subtracted)", file=sys.stderr)
        return 2
    if shutil.which("perf") is None:
        print("profile_suite: perf is not installed (Debian: linux-perf)", file=sys.stderr)
        return 2
    try:
        entries = suite_entries(args.scenes)
    except KeyError as e:
        print(f"profile_suite: {e.args[0]}", file=sys.stderr)
        return 2
    names = [e["name"] for e in entries]
    stages = [s for s, _, _ in STAGES if s != "loading"]
    stages = list(dict.fromkeys(stages)) + ["other"]
    rows = []
    with tempfile.TemporaryDirectory() as td:
        for name in names:
            path = ROOT / "bench" / "suite" / f"{name}.json"
            full = profile(args.binary, path, args.spp, pathlib.Path(td))
            one = profile(args.binary, path, 1, pathlib.Path(td))
            # The render of spp − 1 samples per pixel: each stage's samples less the 1-spp run's.
            diff = {k: max(0.0, full.get(k, 0.0) - one.get(k, 0.0)) for k in stages}
            render = sum(diff.values())
            load = 100.0 * full.get("loading", 0.0) / sum(full.values())
            rows.append((name, {k: 100.0 * diff[k] / render for k in stages}, load))
            print(name, " ".join(f"{k.split(' ')[0]}={v:.0f}" for k, v in rows[-1][1].items()), file=sys.stderr)
    short = {s: s for s in stages}
    lines = [
        "# Where the render time goes, per suite scene",
        "",
        f"`python bench/profile_suite.py --spp {args.spp}`: `perf record` of `pellucid-render SCENE --spp {args.spp} "
        "--threads 1` (the default SIMD target) and of the same at 1 spp, samples grouped by symbol into stages. "
        "Each row is the share of the render's samples: each stage's samples less the 1-spp run's, which leaves "
        f"the render of {args.spp - 1} spp. Start-up and scene loading (the last column) are a share of the full "
        "run's process.",
        "",
        "| scene | " + " | ".join(short[s] for s in stages) + " | start-up and loading (of the process) |",
        "|---|" + "---|" * (len(stages) + 1),
    ]
    for name, pct, load in rows:
        lines.append(f"| {name} | " + " | ".join(f"{pct[s]:.0f} %" for s in stages) + f" | {load:.0f} % |")
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    print(f"wrote {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

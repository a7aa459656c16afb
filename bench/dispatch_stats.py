#!/usr/bin/env python3
"""How full the path tracer's masked packet-form calls are, per suite scene, and what sorting lanes by
material (a wavefront design) could save at most.

    python bench/dispatch_stats.py [--scenes a,b] [--spp 16] [--build-dir build/dispatch-stats]
        [--out bench/results/suite/dispatch.md]

The path tracer shades the materials of a packet with masked calls: each packet form present runs
once on the whole packet, and its own lanes keep the results (integrator/path_kernel.h). A wavefront
design would instead queue the hits of each form and run them in full packets. This script builds the
diagnostic configuration (CMake `-DPELLUCID_DISPATCH_STATS=ON`, its own build folder), in which each
masked call records its active lanes and its time stamp-counter cycles, renders every scene of
bench/suite/suite.json on one thread, and reports per form:

* calls, and utilisation = active lanes / (calls x packet width);
* share = the form's cycles / the kernel's cycles (the render, loading excluded);
* the ideal wavefront saving, share x (1 - utilisation): the render time a design with every form
  call full would save if sorting, moving path state between queues and the lost coherence of
  restarting lanes cost nothing (a masked call with fewer active lanes costs at most a full one, so
  this bounds the saving from above);
* the same for the rest of the packet pass (next-event estimation, MIS, roulette, the next rays),
  whose lanes that go on from a hit are its utilisation: a wavefront would shade only those.

The scene's bound is the sum. Lanes that finish restart at once, so the stages before shading
(camera rays, traversal, hit records) run on nearly full packets in either design.

The diagnostic build reads the clock around every call, so its shares are those of a slightly slower
kernel; the images are the default build's.
"""
from __future__ import annotations

import argparse
import math
import pathlib
import re
import subprocess
import sys
import tempfile
from typing import Dict, List, Tuple

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
from profile_suite import suite_entries  # noqa: E402

# PacketKind (integrator/path_services.h) -> name.
FORMS = {1: "lambertian", 2: "smooth dielectric", 3: "smooth conductor", 4: "rough conductor (GGX)",
         5: "plastic (smooth or GGX)", 6: "rough conductor (Beckmann)", 7: "rough plastic (Beckmann)",
         8: "rough dielectric (GGX)", 9: "rough dielectric (Beckmann)", 10: "principled 2015",
         11: "thin dielectric", 12: "Oren-Nayar", 13: "principled 2012", 14: "principled thin sheet", 15: "principled solid with transmission"}
LINE = re.compile(r"dispatch form (-?\d+) calls (\d+) lanes (\d+) width (\d+) cycles (\d+)")


def build(build_dir: pathlib.Path) -> pathlib.Path:
    """Configure and build pellucid-render with PELLUCID_DISPATCH_STATS=ON; returns the binary."""
    cmake = ROOT / ".venv" / "bin" / "cmake"
    cmake = str(cmake) if cmake.exists() else "cmake"
    ninja = ROOT / ".venv" / "bin" / "ninja"
    gen = ["-G", "Ninja", f"-DCMAKE_MAKE_PROGRAM={ninja}"] if ninja.exists() else []
    subprocess.run([cmake, "-S", str(ROOT), "-B", str(build_dir), *gen, "-DCMAKE_BUILD_TYPE=Release",
                    "-DPELLUCID_DISPATCH_STATS=ON", "-DPELLUCID_BUILD_PYTHON=OFF", "-DPELLUCID_BUILD_TESTS=OFF",
                    "-DPELLUCID_BUILD_APP=ON"], check=True, stdout=subprocess.DEVNULL)
    subprocess.run([cmake, "--build", str(build_dir), "--target", "pellucid_cli", "-j2"], check=True,
                   stdout=subprocess.DEVNULL)
    return build_dir / "cpp" / "pellucid-render"


def measure(binary: pathlib.Path, scene: pathlib.Path, spp: int) -> Dict[int, Tuple[int, int, int, int]]:
    """{form: (calls, lanes, width, cycles)}, form -1 being the kernel's tiles and -2 its packet passes."""
    with tempfile.TemporaryDirectory() as tmp:
        out = subprocess.run([str(binary), str(scene), "--spp", str(spp), "--threads", "1", "-o",
                              str(pathlib.Path(tmp) / "image.exr")], capture_output=True, text=True)
    rows = {int(m.group(1)): (int(m.group(2)), int(m.group(3)), int(m.group(4)), int(m.group(5)))
            for m in LINE.finditer(out.stderr)}
    if -1 not in rows:
        raise RuntimeError(f"{scene.name}: no dispatch counts (is this the diagnostic build?)\n{out.stderr[-2000:]}")
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes", default="", help="comma-separated scene names (default: the whole suite)")
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--build-dir", default=str(ROOT / "build" / "dispatch-stats"))
    ap.add_argument("--out", default=str(ROOT / "bench" / "results" / "suite" / "dispatch.md"))
    a = ap.parse_args(argv)
    binary = build(pathlib.Path(a.build_dir))
    lines: List[str] = [
        "# How full the masked packet-form calls are, per suite scene",
        "",
        f"`python bench/dispatch_stats.py --spp {a.spp}`: the diagnostic build (`-DPELLUCID_DISPATCH_STATS=ON`) on "
        "one thread. Utilisation: active lanes / (calls x width). Share: the form's cycles / the kernel's. "
        "Ideal wavefront saving: share x (1 - utilisation), the most that full form calls could save with "
        "free sorting and moving of path state.",
        "",
        "| scene | width | form | calls | utilisation | share of render | ideal wavefront saving |",
        "|---|---|---|---|---|---|---|",
    ]
    totals: List[Tuple[str, float, float]] = []
    for e in suite_entries(a.scenes):
        rows = measure(binary, ROOT / "bench" / "suite" / e["file"], a.spp)
        kernel = rows[-1][3]
        saving = share_all = 0.0
        for form in sorted(k for k in rows if k >= 0):
            calls, lanes, width, cycles = rows[form]
            util = lanes / (calls * width)
            share = cycles / kernel
            saving += share * (1 - util)
            share_all += share
            lines.append(f"| {e['name']} | {width} | {FORMS.get(form, form)} | {calls} | {util:.2f} | "
                         f"{100 * share:.1f} % | {100 * share * (1 - util):.1f} % |")
        calls, lanes, width, cycles = rows[-2]
        util = lanes / (calls * width)
        rest = cycles / kernel - share_all
        saving += rest * (1 - util)
        lines.append(f"| {e['name']} | {width} | rest of the packet pass | {calls} | {util:.2f} | {100 * rest:.1f} % | "
                     f"{100 * rest * (1 - util):.1f} % |")
        lines.append(f"| **{e['name']}** | | **bound** | | | **{100 * (share_all + rest):.1f} %** | "
                     f"**{100 * saving:.1f} %** |")
        totals.append((e["name"], share_all + rest, saving))
        print(f"{e['name']:20s} packet pass {100 * (share_all + rest):5.1f} % of the render, "
              f"ideal wavefront saving {100 * saving:5.1f} %", flush=True)
    best = max(totals, key=lambda t: t[2])
    geo = math.exp(sum(math.log(1.0 / (1.0 - t[2])) for t in totals) / len(totals))
    lines += ["", f"Largest ideal saving: {best[0]}, {100 * best[2]:.1f} % of its render time. Ideal speed-up "
              f"1 / (1 - saving), geometric mean over the scenes: {geo:.3f}x."]
    print(f"largest {best[0]} {100 * best[2]:.1f} %; geometric mean of the ideal speed-up {geo:.3f}x")
    out = pathlib.Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

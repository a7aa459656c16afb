"""Cornell box benchmark: pellucid against Mitsuba 3 in the same run.

Renders scenes/cornell_box.json at 256x256, 64 spp, max depth 8 with pellucid and reports camera
samples per second and peak memory. When the optional Mitsuba 3 peer is set up
(bench/peers/setup_mitsuba.sh), it renders the same box, converted from the same JSON to Mitsuba's
dict, in scalar_rgb and llvm_ad_rgb, prints the speed ratios, and checks that the images agree
within noise with a per-pixel z-test (two-sided α = 0.01, Šidák-corrected over the pixels; at least
99 % of pixels must pass, as in Mitsuba's own render tests).

    .venv/bin/python bench/cornell.py [--spp 64] [--threads 2] [--repeats 3] [--csv bench/results/cornell.csv]

Speed is a ratio measured in one run on one machine, never an absolute figure in a test.
"""
from __future__ import annotations

import argparse
import json
import pathlib
import resource
import statistics
import subprocess
import sys
import tempfile

import numpy as np

from pellucid.bench import mitsuba_python, z_test

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "cornell_box.json"
MITSUBA_PY = mitsuba_python() or ROOT / "bench" / ".venv-mitsuba" / "bin" / "python"  # or $PELLUCID_MITSUBA_PYTHON
RUNNER = ROOT / "bench" / "peers" / "mitsuba_runner.py"

# Child process: render with pellucid and print stats as JSON (so peak memory is its own).
_CHILD = r"""
import json, sys, resource, numpy as np, pellucid
scene_path, spp, threads, seed, out = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
d = json.load(open(scene_path))
d["film"]["width"] = d["film"]["height"] = 256
d["integrator"]["max_depth"] = 8
scene = pellucid.load_dict(d)
pellucid.render(scene, spp=1, seed=seed + 1000, threads=threads)  # warm caches, as for the peers
img, var, st = pellucid.render_with_stats(scene, spp=spp, seed=seed, threads=threads)
np.save(out + ".img.npy", img); np.save(out + ".var.npy", var)
st["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
print(json.dumps(st))
"""


def run_pellucid(spp: int, threads: int, seed: int, tmp: pathlib.Path) -> dict:
    out = str(tmp / f"pellucid_{seed}")
    r = subprocess.run([sys.executable, "-c", _CHILD, str(SCENE), str(spp), str(threads), str(seed), out],
                       capture_output=True, text=True, check=True)
    st = json.loads(r.stdout.strip().splitlines()[-1])
    st["image"], st["variance"] = np.load(out + ".img.npy"), np.load(out + ".var.npy")
    st["samples_per_second"] = st["samples"] / st["seconds"]
    return st


def run_mitsuba(variant: str, spp: int, threads: int, seed: int, tmp: pathlib.Path, passes: int) -> dict:
    out = tmp / f"mitsuba_{variant}_{seed}.exr"
    report = tmp / f"mitsuba_{variant}_{seed}.json"
    cmd = [str(MITSUBA_PY), str(RUNNER), str(SCENE), "--variant", variant, "--spp", str(spp), "--seed", str(seed),
           "--out", str(out), "--threads", str(threads), "--max-depth", "8", "--passes", str(passes),
           "--json-report", str(report)]
    subprocess.run(cmd, capture_output=True, text=True, check=True)
    st = json.loads(report.read_text())
    import pellucid

    st["image"] = pellucid.read_image(out)
    var_path = pathlib.Path(str(out)[:-4] + ".var.exr")
    st["variance"] = pellucid.read_image(var_path) if var_path.exists() else None
    return st


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--csv", type=pathlib.Path, default=None)
    args = ap.parse_args()

    rows = []
    with tempfile.TemporaryDirectory() as td:
        tmp = pathlib.Path(td)
        ours = [run_pellucid(args.spp, args.threads, seed, tmp) for seed in range(args.repeats)]
        ours_sps = statistics.median(o["samples_per_second"] for o in ours)
        print(f"pellucid     : {ours_sps / 1e6:6.3f} M samples/s (median of {args.repeats}), "
              f"{statistics.median(o['seconds'] for o in ours):.3f} s, peak RSS {ours[0]['peak_rss_mb']:.0f} MB")
        rows.append(("pellucid", ours_sps, statistics.median(o["seconds"] for o in ours)))
        if not (MITSUBA_PY.exists() and RUNNER.exists()):
            print("Mitsuba 3 not set up (bash bench/peers/setup_mitsuba.sh); pellucid figures only.")
        else:
            for variant in ("scalar_rgb", "llvm_ad_rgb"):
                runs = [run_mitsuba(variant, args.spp, args.threads, seed, tmp, passes=1) for seed in range(args.repeats)]
                sps = statistics.median(r["samples_per_second"] for r in runs)
                rows.append((variant, sps, statistics.median(r["seconds"] for r in runs)))
                print(f"mitsuba {variant:11s}: {sps / 1e6:6.3f} M samples/s; pellucid is {ours_sps / sps:.2f}x")
            # Agreement: both renderers' means with per-pixel variances (Mitsuba's from 16 passes).
            ref = run_mitsuba("llvm_ad_rgb", 1024, args.threads, 123, tmp, passes=16)
            frac, zc = z_test(ours[0]["image"], ours[0]["variance"], ref["image"], ref["variance"])
            print(f"per-pixel z-test vs Mitsuba llvm_ad_rgb (1024 spp): {100 * frac:.2f}% of pixel channels "
                  f"within |z| <= {zc:.2f} -> {'PASS' if frac >= 0.99 else 'FAIL'}")
            rows.append(("z_test_pass_fraction", frac, 0.0))
    if args.csv:
        args.csv.parent.mkdir(parents=True, exist_ok=True)
        with open(args.csv, "w") as f:
            f.write("renderer,samples_per_second,seconds\n")
            for r in rows:
                f.write(f"{r[0]},{r[1]:.6g},{r[2]:.6g}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

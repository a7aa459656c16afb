#!/usr/bin/env bash
# Regenerate the committed speed-against-accuracy results in bench/results/ (one run per scene).
# SPDX-License-Identifier: Apache-2.0
#
#   bash bench/run_results.sh [cornell|cornell_box_filter|veach|env|all]     (default: all)
#
# Needs the project venv (make deps) and, for the peers, bench/peers/setup_mitsuba.sh (or
# PELLUCID_MITSUBA_PYTHON pointing at a python with mitsuba). Run on an idle machine: every
# renderer is timed with all cores (--threads 2 on the project's 2-core machines).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
PY="${PY:-.venv/bin/python}"
THREADS="${THREADS:-2}"
bench() { "$PY" -m pellucid.bench "$@"; }
what="${1:-all}"

if [[ $what == cornell || $what == all ]]; then
  bench scenes/cornell_box.json --methods bsdf,nee,mis,mis+sobol,scalar_rgb,llvm_ad_rgb --budgets 0.5,1,2,5,10 \
    --reference-spp 4096 --threads "$THREADS" --out-dir bench/results --name cornell_box
fi
if [[ $what == cornell_box_filter || $what == all ]]; then
  # The same box with a box pixel filter for every renderer: each sample feeds one pixel, so per-pixel
  # noise compares the light transport alone (Mitsuba splats a gaussian sample over ~3x3 pixels,
  # pellucid importance-samples the filter; that alone gives Mitsuba ~3x lower per-pixel relMSE per spp).
  bench scenes/cornell_box.json --methods bsdf,nee,mis,mis+sobol,scalar_rgb,llvm_ad_rgb --budgets 0.5,1,2,5,10 \
    --reference-spp 4096 --threads "$THREADS" --out-dir bench/results --name cornell_box_boxfilter --filter box
fi
if [[ $what == veach || $what == all ]]; then
  bench scenes/veach_mis.json --methods bsdf,nee,mis,mis+sobol,scalar_rgb,llvm_ad_rgb --budgets 0.5,1,2,5,10 \
    --reference-spp 4096 --threads "$THREADS" --out-dir bench/results --name veach_mis \
    --crop 0,100,320,140 --agreement-spp 256
fi
if [[ $what == env || $what == all ]]; then
  bench scenes/env_spheres.json --methods bsdf,nee,mis,mis+sobol,scalar_rgb,llvm_ad_rgb --budgets 0.5,1,2,5,10 \
    --reference-spp 4096 --threads "$THREADS" --out-dir bench/results --name env_spheres \
    --crop 60,50,200,100 --agreement-spp 256
fi

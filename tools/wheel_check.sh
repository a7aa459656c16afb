#!/usr/bin/env bash
# The portable wheel on a Debian 12 with no development packages.
#
# Builds the wheel with tools/build_wheel.sh on this machine, then builds a minbase Debian 12
# (bookworm) root with debootstrap holding only python3, python3-venv, ca-certificates and the
# system libraries that a manylinux wheel may assume (PEP 600; auditwheel leaves them out of the
# wheel) and that ours loads: glib/gobject and the X11 client libraries X11, Xext and Xrender.
# No compiler, no -dev package, none of Embree, OpenImageIO or TBB. Inside it with chroot, a new
# virtual environment installs the wheel (numpy comes from PyPI), `pellucid-render` renders
# scenes/cornell_box.json to EXR and PNG, and Python renders the same scene with the same seed and
# must get the same image. Only the host's network settings go into the root (/etc/resolv.conf, the
# CA bundle, pip's configuration). If the Debian mirror cannot be reached the script says so on one
# line and exits 0 (it proves nothing then, and does not pretend to).
#
# Usage: tools/wheel_check.sh [--wheel FILE] [--keep]
#   --wheel FILE  check this wheel instead of building one
#   --keep        leave the root in place afterwards (default: removed)
# Environment: DEBIAN_MIRROR (default http://deb.debian.org/debian). Needs root (debootstrap, chroot).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mirror="${DEBIAN_MIRROR:-http://deb.debian.org/debian}"
keep=0
wheel=""
while [ $# -gt 0 ]; do
    case "$1" in
        --keep) keep=1 ;;
        --wheel) wheel="$(cd "$(dirname "$2")" && pwd)/$(basename "$2")"; shift ;;
        -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
        *) echo "wheel_check: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
    shift
done
LDR_NAME=wheel_check
# shellcheck source=tools/lib_debian_root.sh
source "$repo/tools/lib_debian_root.sh"
ldr_require_root
ldr_mirror_or_skip

root="$(mktemp -d /var/tmp/pellucid-wheel-root.XXXXXX)"
dist="$(mktemp -d /var/tmp/pellucid-wheel-dist.XXXXXX)"
ldr_cleanup_extra() { rm -rf "$dist"; }
ldr_trap_cleanup

if [ -z "$wheel" ]; then
    step "build the wheel"
    bash "$repo/tools/build_wheel.sh" --out "$dist" > "$dist.log" 2>&1 || {
        tail -40 "$dist.log" >&2; rm -f "$dist.log"
        echo "wheel_check: FAILED: tools/build_wheel.sh (log tail above)" >&2
        exit 1
    }
    grep '^build_wheel:' "$dist.log" | sed 's/^/wheel_check:   /'
    rm -f "$dist.log"
    wheel="$(ls "$dist"/pellucid-*.whl)"
fi

ldr_ensure_debootstrap

# The manylinux-assumed libraries the wheel needs (see the list that `auditwheel show` prints).
manylinux_libs=libglib2.0-0,libx11-6,libxext6,libxrender1
ldr_debootstrap python3,python3-venv,ca-certificates,$manylinux_libs

step "network settings + files"
ldr_copy_network_settings
mkdir -p "$root/check"
cp "$wheel" "$root/check/"
cp "$repo/scenes/cornell_box.json" "$root/check/"
ldr_mount_proc
ldr_enter /check

# The root really has none of what a source build needs.
devs="$(in_root "dpkg-query -W -f='\${Package}\n' | grep -E -- '-dev\$|^(gcc|g\+\+|cpp)(-[0-9]+)?\$|^libembree|^libopenimageio|^libtbb' || true")"
if [ -n "$devs" ]; then
    echo "wheel_check: FAILED: the root is not bare; it has: $(echo $devs)" >&2
    exit 1
fi

step "pip install the wheel"
in_root "python3 -m venv venv && venv/bin/python -m pip install -q $(basename "$wheel")" > "$root.pip.log" 2>&1 || {
    tail -30 "$root.pip.log" >&2; rm -f "$root.pip.log"
    echo "wheel_check: FAILED: pip install of the wheel in the bare root (log tail above)" >&2
    exit 1
}
rm -f "$root.pip.log"
# Every library the extension and the executable load is in the wheel or in the root.
missing="$(in_root "ldd venv/lib/python3*/site-packages/pellucid/_core*.so venv/lib/python3*/site-packages/pellucid/bin/pellucid-render | grep 'not found' | sort -u || true")"
if [ -n "$missing" ]; then
    echo "wheel_check: FAILED: libraries neither bundled nor in the root:" >&2
    echo "$missing" >&2
    exit 1
fi

step "render (CLI and Python)"
in_root "venv/bin/pellucid-render cornell_box.json -o box.exr -o box.png --spp 16 --seed 5 -q" || {
    echo "wheel_check: FAILED: pellucid-render in the bare root" >&2
    exit 1
}
in_root "venv/bin/python - <<'EOF'
import numpy as np
import pellucid
cli = pellucid.read_image('box.exr')
img = pellucid.render(pellucid.load_file('cornell_box.json'), spp=16, seed=5)
img.save('box_py.png')
assert img.shape == cli.shape and np.isfinite(img).all() and img.mean() > 0.01, (img.shape, img.mean())
assert np.array_equal(img, cli), 'pellucid-render and pellucid.render differ for the same seed'
print(f'wheel_check:   rendered {img.width}x{img.height}, mean {img.mean():.4f}; CLI and Python images identical')
EOF" || {
    echo "wheel_check: FAILED: rendering from Python in the bare root" >&2
    exit 1
}
for f in box.png box_py.png; do
    [ -s "$root/check/$f" ] || { echo "wheel_check: FAILED: no $f written" >&2; exit 1; }
done
step ""
echo "wheel_check: all steps $(( $(date +%s) - t_start )) s"
echo "wheel_check: PASSED"

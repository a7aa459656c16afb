#!/usr/bin/env bash
# The README's two commands on a truly fresh Debian 12.
#
# Builds a minbase Debian 12 (bookworm) root with debootstrap, with nothing in it but make, git,
# python3 and ca-certificates (the README's prerequisites), clones this repository's HEAD into it and
# runs `make render` and then `make test` inside it with chroot. Only the host's network settings go
# into the root: /etc/resolv.conf, the CA bundle and pip's configuration files. Each step's time and
# the test summaries are printed; any failure exits non-zero. If the Debian mirror cannot be reached
# the script says so on one line and exits 0 (it proves nothing then, and does not pretend to).
#
# Usage: tools/fresh_check.sh [--keep] [--root DIR]
#   --keep      leave the root in place afterwards (default: removed)
#   --root DIR  where to build the root (default: a new directory under /var/tmp)
# Environment: DEBIAN_MIRROR (default http://deb.debian.org/debian). Needs root (debootstrap, chroot).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mirror="${DEBIAN_MIRROR:-http://deb.debian.org/debian}"
keep=0
root=""
while [ $# -gt 0 ]; do
    case "$1" in
        --keep) keep=1 ;;
        --root) root="$2"; shift ;;
        -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
        *) echo "fresh_check: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
    shift
done

LDR_NAME=fresh_check
# shellcheck source=tools/lib_debian_root.sh
source "$repo/tools/lib_debian_root.sh"
ldr_require_root
ldr_mirror_or_skip
ldr_ensure_debootstrap

if [ -z "$root" ]; then
    root="$(mktemp -d /var/tmp/pellucid-fresh.XXXXXX)"
else
    mkdir -p "$root"
    if [ -n "$(ls -A "$root")" ]; then
        echo "fresh_check: --root $root is not empty" >&2
        exit 2
    fi
fi
ldr_trap_cleanup

ldr_debootstrap make,git,python3,ca-certificates

step "network settings + source"
ldr_copy_network_settings
# The committed HEAD, as a new user would clone it.
git clone -q --no-hardlinks "$repo" "$root/src/pellucid"
ldr_mount_proc
ldr_enter /src/pellucid

step "make render (first)"
in_root "make render" > "$root.render.log" 2>&1 || {
    tail -40 "$root.render.log" >&2
    echo "fresh_check: FAILED: make render on the fresh root (log tail above)" >&2
    rm -f "$root.render.log"
    exit 1
}
render_s=$(( $(date +%s) - step_start ))
rm -f "$root.render.log"
if [ ! -s "$root/src/pellucid/out/cornell_box.png" ]; then
    echo "fresh_check: FAILED: make render wrote no out/cornell_box.png" >&2
    exit 1
fi

step "make test"
set +e
in_root "make test" > "$root.test.log" 2>&1
rc=$?
set -e
# The summaries: ctest's and pytest's closing lines.
grep -E "tests passed|tests failed|^[0-9]+ (passed|failed)|^=+ .*(passed|failed|error)" "$root.test.log" \
    | sed 's/^/fresh_check:   /' || true
if [ $rc != 0 ]; then
    tail -60 "$root.test.log" >&2
    rm -f "$root.test.log"
    echo "fresh_check: FAILED: make test on the fresh root (exit $rc, log tail above)" >&2
    exit 1
fi
rm -f "$root.test.log"
step ""
echo "fresh_check: first make render took ${render_s} s; all steps $(( $(date +%s) - t_start )) s"
echo "fresh_check: PASSED"

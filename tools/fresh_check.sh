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

if [ "$(id -u)" != 0 ]; then
    echo "fresh_check: needs root (debootstrap and chroot)" >&2
    exit 2
fi

t_start=$(date +%s)
step_start=$t_start
step() {  # step NAME: print the time of the step that just ended, then start NAME
    local now; now=$(date +%s)
    [ -n "${step_name:-}" ] && printf 'fresh_check: %-28s %5d s\n' "$step_name" $((now - step_start))
    step_name="$1"; step_start=$now
}

# The mirror: one line and exit 0 when it cannot be reached.
if ! python3 - "$mirror" <<'EOF' >/dev/null 2>&1
import sys, urllib.request
urllib.request.urlopen(sys.argv[1].rstrip("/") + "/dists/bookworm/Release", timeout=20).read(64)
EOF
then
    echo "fresh_check: SKIPPED: the Debian mirror $mirror cannot be reached"
    exit 0
fi

if ! command -v debootstrap >/dev/null 2>&1; then
    step "install debootstrap (host)"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends debootstrap >/dev/null
fi

if [ -z "$root" ]; then
    root="$(mktemp -d /var/tmp/pellucid-fresh.XXXXXX)"
else
    mkdir -p "$root"
    if [ -n "$(ls -A "$root")" ]; then
        echo "fresh_check: --root $root is not empty" >&2
        exit 2
    fi
fi

mounted=()
cleanup() {
    local rc=$?
    for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do
        umount "${mounted[$i]}" 2>/dev/null || umount -l "${mounted[$i]}" 2>/dev/null || true
    done
    # Never delete through a mount that is still there.
    if [ "$keep" = 0 ] && ! grep -q " $root/" /proc/mounts; then
        rm -rf --one-file-system "$root"
    elif [ "$keep" = 1 ]; then
        echo "fresh_check: root kept at $root"
    fi
    exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT TERM

step "debootstrap minbase"
if ! debootstrap --variant=minbase --include=make,git,python3,ca-certificates bookworm "$root" "$mirror" \
        > "$root.debootstrap.log" 2>&1; then
    if grep -qiE "Failed getting release file|Couldn't download|Temporary failure resolving|Connection (refused|timed out)" "$root.debootstrap.log"; then
        echo "fresh_check: SKIPPED: the Debian mirror $mirror could not be reached during debootstrap"
        rm -f "$root.debootstrap.log"
        exit 0
    fi
    tail -20 "$root.debootstrap.log" >&2
    echo "fresh_check: FAILED: debootstrap (log above)" >&2
    rm -f "$root.debootstrap.log"
    exit 1
fi
rm -f "$root.debootstrap.log"

step "network settings + source"
# Network settings only: name resolution, the CA bundle and pip's configuration.
cp -L /etc/resolv.conf "$root/etc/resolv.conf"
if [ -f /etc/ssl/certs/ca-certificates.crt ]; then
    mkdir -p "$root/etc/ssl/certs"
    cp -L /etc/ssl/certs/ca-certificates.crt "$root/etc/ssl/certs/ca-certificates.crt"
fi
for f in /etc/pip.conf /etc/xdg/pip/pip.conf "${HOME:-/root}/.config/pip/pip.conf" "${HOME:-/root}/.pip/pip.conf" \
         "${PIP_CONFIG_FILE:-}"; do
    [ -n "$f" ] && [ -f "$f" ] || continue
    case "$f" in
        "${HOME:-/root}"/*) dest="$root/root/${f#"${HOME:-/root}"/}" ;;
        *) dest="$root$f" ;;
    esac
    mkdir -p "$(dirname "$dest")"
    cp -L "$f" "$dest"
done
# The committed HEAD, as a new user would clone it.
git clone -q --no-hardlinks "$repo" "$root/src/pellucid"

mount -t proc proc "$root/proc"
mounted+=("$root/proc")

# A clean environment: nothing of the host's but the proxy settings.
envs=(HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin LANG=C.UTF-8 TERM=dumb)
for v in http_proxy https_proxy no_proxy HTTP_PROXY HTTPS_PROXY NO_PROXY; do
    [ -n "${!v:-}" ] && envs+=("$v=${!v}")
done
in_root() { chroot "$root" /usr/bin/env -i "${envs[@]}" /bin/bash -c "cd /src/pellucid && $1"; }

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

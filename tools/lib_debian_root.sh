# Shared part of tools/fresh_check.sh and tools/wheel_check.sh: a minbase Debian 12 (bookworm) root
# made with debootstrap, entered with chroot.
# SPDX-License-Identifier: Apache-2.0
#
# Sourced, not run. The calling script sets, before it calls these functions:
#   LDR_NAME  the prefix of every message ("fresh_check", "wheel_check")
#   mirror    the Debian mirror (the scripts take DEBIAN_MIRROR, default http://deb.debian.org/debian)
#   root      the directory of the root (once it exists)
#   keep      1: leave the root in place at exit, 0: remove it
# and may define ldr_cleanup_extra, which the exit handler calls after unmounting (to remove the
# script's own temporary files). Only the host's network settings go into the root:
# /etc/resolv.conf, the CA bundle and pip's configuration files (and the files they name).

t_start=$(date +%s)
step_start=$t_start
step_name=""
mounted=()

step() {  # step NAME: print the time of the step that just ended, then start NAME
    local now; now=$(date +%s)
    [ -n "${step_name:-}" ] && printf '%s: %-28s %5d s\n' "$LDR_NAME" "$step_name" $((now - step_start))
    step_name="$1"; step_start=$now
}

# Exit 2 unless running as root (debootstrap and chroot need it).
ldr_require_root() {
    if [ "$(id -u)" != 0 ]; then
        echo "$LDR_NAME: needs root (debootstrap and chroot)" >&2
        exit 2
    fi
}

# The mirror: one SKIPPED line and exit 0 when it cannot be reached (the check proves nothing then,
# and does not pretend to).
ldr_mirror_or_skip() {
    if ! python3 - "$mirror" <<'EOF' >/dev/null 2>&1
import sys, urllib.request
urllib.request.urlopen(sys.argv[1].rstrip("/") + "/dists/bookworm/Release", timeout=20).read(64)
EOF
    then
        echo "$LDR_NAME: SKIPPED: the Debian mirror $mirror cannot be reached"
        exit 0
    fi
}

# Install debootstrap on the host when it is missing.
ldr_ensure_debootstrap() {
    if ! command -v debootstrap >/dev/null 2>&1; then
        step "install debootstrap (host)"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends debootstrap >/dev/null
    fi
}

# The exit handler: unmount what was mounted (last first), run ldr_cleanup_extra if defined, then
# remove the root unless --keep (never through a mount that is still there).
_ldr_cleanup() {
    local rc=$?
    for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do
        umount "${mounted[$i]}" 2>/dev/null || umount -l "${mounted[$i]}" 2>/dev/null || true
    done
    if declare -F ldr_cleanup_extra >/dev/null; then
        ldr_cleanup_extra
    fi
    if [ "$keep" = 0 ] && ! grep -q " $root/" /proc/mounts; then
        rm -rf --one-file-system "$root"
    elif [ "$keep" = 1 ]; then
        echo "$LDR_NAME: root kept at $root"
    fi
    exit $rc
}

ldr_trap_cleanup() {
    trap _ldr_cleanup EXIT
    trap 'exit 130' INT TERM
}

# ldr_debootstrap PACKAGES: a minbase bookworm root in $root with the comma-separated PACKAGES.
# A mirror lost during the download gives the SKIPPED line and exit 0; any other failure exits 1.
ldr_debootstrap() {
    step "debootstrap minbase"
    if ! debootstrap --variant=minbase --include="$1" bookworm "$root" "$mirror" \
            > "$root.debootstrap.log" 2>&1; then
        if grep -qiE "Failed getting release file|Couldn't download|Temporary failure resolving|Connection (refused|timed out)" "$root.debootstrap.log"; then
            echo "$LDR_NAME: SKIPPED: the Debian mirror $mirror could not be reached during debootstrap"
            rm -f "$root.debootstrap.log"
            exit 0
        fi
        tail -20 "$root.debootstrap.log" >&2
        echo "$LDR_NAME: FAILED: debootstrap (log above)" >&2
        rm -f "$root.debootstrap.log"
        exit 1
    fi
    rm -f "$root.debootstrap.log"
}

# Network settings only: name resolution, the CA bundle and pip's configuration.
ldr_copy_network_settings() {
    local f dest
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
        ldr_copy_files_named_in "$f"
    done
}

# ldr_copy_files_named_in CONF: the files a pip configuration names by absolute path (a constraint
# or requirement file, a certificate), copied to the same path in the root, so that the copied
# configuration does not point at a file the root lacks (pip then refuses every install).
ldr_copy_files_named_in() {
    local path
    sed -nE 's/^[[:space:]]*(constraint|constraints|requirement|requirements|cert|client-cert)[[:space:]]*[=:][[:space:]]*(\/[^[:space:]]+)[[:space:]]*$/\2/p' "$1" |
    while read -r path; do
        if [ -f "$path" ] && [ ! -e "$root$path" ]; then
            mkdir -p "$root$(dirname "$path")"
            cp -L "$path" "$root$path"
        fi
    done
}

# /proc in the root, unmounted by the exit handler.
ldr_mount_proc() {
    mount -t proc proc "$root/proc"
    mounted+=("$root/proc")
}

# ldr_enter DIR: define in_root CMD, which runs CMD with bash in DIR inside the root, in a clean
# environment: nothing of the host's but the proxy settings.
ldr_enter() {
    ldr_workdir="$1"
    ldr_envs=(HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin LANG=C.UTF-8 TERM=dumb)
    local v
    for v in http_proxy https_proxy no_proxy HTTP_PROXY HTTPS_PROXY NO_PROXY; do
        [ -n "${!v:-}" ] && ldr_envs+=("$v=${!v}")
    done
    return 0
}
in_root() { chroot "$root" /usr/bin/env -i "${ldr_envs[@]}" /bin/bash -c "cd $ldr_workdir && $1"; }

#!/usr/bin/env bash
# Run a command inside a Debian root that has another FreeCAD than the host's.
#
#   tools/debian_root.sh VERSION [COMMAND ...]      default COMMAND: make test
#
#   VERSION  1.1   Debian sid       (FreeCAD 1.1, Qt 6 / PySide6, Python 3.14)
#            1.0   Debian trixie    (FreeCAD 1.0, Qt 5 / PySide2, Python 3.13)
#            0.20  Debian bookworm  (FreeCAD 0.20, the host's; a fresh minimal Debian 12,
#                                    to check that set-up needs nothing the host happens to have)
#
# The root is built once with debootstrap (--variant=minbase) and cached outside the
# repository, in $CADROBOT_ROOTS (default /var/cache/cadrobot/roots). FreeCAD and the
# Python packages are not baked in: COMMAND is normally `make test`, whose own set-up
# (tools/setup.sh) installs them inside the root the way it does on the host, so the
# project's set-up is what is tested there too; the root keeps them for the next run.
#
# For the run, /proc, /sys, /dev, /dev/pts and /dev/shm are mounted into the root, the
# repository is bind-mounted at its own path (nothing beside it: the tests read only the
# repository), the host's resolv.conf and CA certificates are copied in, and COMMAND
# runs with a clean environment (CI is passed on). Every mount is undone on exit, on
# error and on Ctrl-C; runs of the same root wait for each other (flock).
set -euo pipefail

REPO="$(cd "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/.." && pwd -P)"
ROOTS="${CADROBOT_ROOTS:-/var/cache/cadrobot/roots}"
MIRROR="${CADROBOT_DEBIAN_MIRROR:-http://deb.debian.org/debian}"

say() { printf 'debian_root: %s\n' "$*"; }
die() { printf 'debian_root: ERROR: %s\n' "$*" >&2; exit 1; }

case "${1:-}" in
    1.1) SUITE=sid ;;
    1.0) SUITE=trixie ;;
    0.20) SUITE=bookworm ;;
    *) die "usage: tools/debian_root.sh 1.1|1.0|0.20 [COMMAND ...]" ;;
esac
VERSION="$1"; shift
[ $# -gt 0 ] || set -- make test
[ "$(id -u)" -eq 0 ] || die "needs root (debootstrap, mount and chroot)"
ROOT="$ROOTS/$SUITE"

ensure_debootstrap() {
    command -v debootstrap >/dev/null 2>&1 && return 0
    say "apt-get install debootstrap"
    # One apt at a time (the lock tools/setup.sh takes): in CI the host's set-up and the
    # other root's build run beside this one, and apt-get fails at once on a held lock.
    local one_apt=(flock /var/lib/apt/cadrobot.lock apt-get -o DPkg::Lock::Timeout=900)
    DEBIAN_FRONTEND=noninteractive "${one_apt[@]}" update -q >/dev/null \
        && DEBIAN_FRONTEND=noninteractive "${one_apt[@]}" install -y -q debootstrap >/dev/null \
        || die "could not install debootstrap"
}

build_root() {
    [ -f "$ROOT/.cadrobot-root" ] && return 0
    ensure_debootstrap
    local log="$ROOTS/$SUITE-debootstrap.log" partial="$ROOT.partial"
    rm -rf "$partial"
    say "building the $SUITE root in $ROOT (FreeCAD $VERSION; log: $log)"
    # make: the command inside is `make ...`; ca-certificates: apt and pip over https.
    if ! debootstrap --variant=minbase --include=make,ca-certificates \
            "$SUITE" "$partial" "$MIRROR" >"$log" 2>&1; then
        tail -n 20 "$log" >&2
        die "debootstrap $SUITE failed (log: $log)"
    fi
    # The mirror's sid Release file may be past its Valid-Until date.
    printf 'Acquire::Check-Valid-Until "false";\n' >"$partial/etc/apt/apt.conf.d/99cadrobot"
    printf '%s\n' "$SUITE" >"$partial/.cadrobot-root"
    mv "$partial" "$ROOT"
}

MOUNTED=()
mount_into() {  # mount_into TARGET-INSIDE-ROOT MOUNT-ARGS...
    local target="$ROOT$1"; shift
    mkdir -p "$target"
    mount "$@" "$target"
    MOUNTED+=("$target")
}

cleanup() {
    local i
    for ((i = ${#MOUNTED[@]} - 1; i >= 0; i--)); do
        umount "${MOUNTED[$i]}" 2>/dev/null || umount -l "${MOUNTED[$i]}" 2>/dev/null || true
    done
    MOUNTED=()
}

# One run per root at a time (a second would unmount the first one's /proc and /dev),
# and mounts left by a run that was killed are undone first.
mkdir -p "$ROOTS"
exec 9>"$ROOTS/$SUITE.lock"
flock 9
stale_mounts() { awk -v root="$ROOT/" 'index($2, root) == 1 {print $2}' /proc/mounts | sort -r; }
for mounted in $(stale_mounts); do umount -l "$mounted" 2>/dev/null || true; done

build_root
trap cleanup EXIT
trap 'exit 130' INT TERM
mount_into /proc -t proc proc
mount_into /sys --rbind /sys
mount --make-rslave "$ROOT/sys"
mount_into /dev --bind /dev
mount_into /dev/pts --bind /dev/pts
mount_into /dev/shm -t tmpfs -o mode=1777 shm
mount_into "$REPO" --bind "$REPO"
cp -L /etc/resolv.conf "$ROOT/etc/resolv.conf"
# The host's CA bundle, for a host behind a proxy that re-signs TLS.
cp -L /etc/ssl/certs/ca-certificates.crt "$ROOT/etc/ssl/certs/ca-certificates.crt" 2>/dev/null || true

say "FreeCAD $VERSION ($SUITE root $ROOT): $*"
set +e
chroot "$ROOT" /usr/bin/env -i HOME=/root LANG=C.UTF-8 TERM="${TERM:-dumb}" \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    ${CI:+CI="$CI"} ${CADROBOT_DEBUG:+CADROBOT_DEBUG="$CADROBOT_DEBUG"} \
    /bin/sh -c 'cd "$1" && shift && exec "$@"' sh "$REPO" "$@"
code=$?
set -e
exit "$code"

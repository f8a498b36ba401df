#!/usr/bin/env bash
# The guides' install, followed literally on the robot's own OS (issue 34): a Debian 12
# bookworm userland of the board's architecture under QEMU user-mode emulation, the
# guide's install blocks run as written, then ego --version, ego demo, a controller on a
# pty emulator in another process, the unit and camera tests, and the extras (record,
# dashboard, Zenoh).
#
#   sudo tools/board_check.sh [armhf|arm64 ...]   (default: both)
#
#   armhf: the Gumstix Overo (ARMv7), docs/guide/overo.md
#   arm64: the Pi-puck's Raspberry Pi Zero 2 W, docs/guide/pipuck.md
#
# Needs root (chroot, mounts), debootstrap, qemu-user-static and binfmt-support (installed
# here with apt-get if missing) and the network to Debian's mirror and PyPI. The base
# userland is built once with debootstrap and kept in $EGO_BOARD_CACHE (default
# /var/cache/ego-board, outside the repository); every run installs into a fresh copy.
# Where binfmt_misc is not mounted (a container), it is mounted here; where it cannot be,
# nothing foreign runs and the script says so.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
cache=${EGO_BOARD_CACHE:-/var/cache/ego-board}
mirror=${EGO_DEBIAN_MIRROR:-http://deb.debian.org/debian}
arches=("$@")
[ ${#arches[@]} -gt 0 ] || arches=(armhf arm64)
[ "$(id -u)" -eq 0 ] || { echo "board_check: run as root (chroot and mounts)" >&2; exit 2; }

if ! command -v debootstrap >/dev/null || ! [ -e /usr/bin/qemu-arm-static ]; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap qemu-user-static binfmt-support
fi
if ! [ -e /proc/sys/fs/binfmt_misc/register ]; then
    mount -t binfmt_misc binfmt_misc /proc/sys/fs/binfmt_misc
fi
update-binfmts --enable qemu-arm >/dev/null 2>&1 || true
update-binfmts --enable qemu-aarch64 >/dev/null 2>&1 || true
for handler in qemu-arm qemu-aarch64; do
    grep -q enabled "/proc/sys/fs/binfmt_misc/$handler" 2>/dev/null \
        || { echo "board_check: binfmt_misc has no $handler handler" >&2; exit 2; }
done

# The wheel the guides copy to the board, in a folder of this run's own (two runs, one a
# board, may go side by side).
mkdir -p "$cache"
dist=$(mktemp -d "$cache/dist.XXXXXX")
trap 'rm -rf "$dist"' EXIT
python3 -m pip wheel --quiet --no-deps -w "$dist" . >/dev/null
wheel=$(ls "$dist"/ego-*.whl)

# The guide's install blocks: every ```sh block that installs into ~/ego with pip.
install_blocks() {
    python3 - "$1" <<'EOF'
import re, sys
text = open(sys.argv[1]).read()
for block in re.findall(r"```sh\n(.*?)```", text, re.S):
    if "~/ego/bin/pip install" in block:
        print(block, end="")
EOF
}

chroot_run() {  # chroot_run ROOT COMMAND...: as root, in a login-like environment
    local root=$1; shift
    chroot "$root" /usr/bin/env -i HOME=/root PATH=/usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin \
        LANG=C.UTF-8 DEBIAN_FRONTEND=noninteractive TERM=dumb \
        ${PIP_CERT:+PIP_CERT=/etc/ssl/certs/ca-certificates.crt} "$@"
}

check_arch() {
    local arch=$1 guide
    case $arch in
        armhf) guide=docs/guide/overo.md ;;
        arm64) guide=docs/guide/pipuck.md ;;
        *) echo "board_check: unknown architecture $arch" >&2; return 2 ;;
    esac
    local base=$cache/rootfs-$arch root=$cache/work-$arch start
    start=$(date +%s)
    if ! [ -x "$base/usr/bin/python3" ]; then
        echo "== $arch: debootstrap bookworm (once; about 15 minutes)"
        rm -rf "$base"
        debootstrap --arch="$arch" --include=python3,ca-certificates bookworm "$base" "$mirror" \
            >"$cache/debootstrap-$arch.log"
    fi
    umount_all "$root"
    if [ "${EGO_BOARD_REUSE:-0}" = 1 ] && [ -d "$root/root/ego" ]; then
        echo "== $arch: EGO_BOARD_REUSE=1: the last run's board, its install blocks run again"
    else
        rm -rf "$root" && cp -a "$base" "$root"
    fi
    cp /etc/resolv.conf "$root/etc/resolv.conf"
    # A network whose TLS goes through a proxy with its own certificate authority (as
    # here): the board trusts what this machine trusts, for apt and pip alike.
    if [ -n "${PIP_CERT:-}" ] && [ -f "$PIP_CERT" ]; then
        cp "$PIP_CERT" "$root/etc/ssl/certs/ca-certificates.crt"
        mkdir -p "$root/usr/local/share/ca-certificates"
        cp "$PIP_CERT" "$root/usr/local/share/ca-certificates/board-check-host.crt"
    fi
    # apt-get as a person answers yes; the guide's `sudo` is root here.
    echo 'APT::Get::Assume-Yes "true";' >"$root/etc/apt/apt.conf.d/90board-check"
    mount -t proc proc "$root/proc"
    mount --bind /dev "$root/dev"
    mount --bind /dev/pts "$root/dev/pts"
    mount -t tmpfs tmpfs "$root/tmp"
    # Unmounted however the check ends (a failed step exits the script through set -e).
    trap 'umount_all "'"$root"'"' EXIT
    cp "$wheel" "$root/root/"
    mkdir -p "$root/root/src"
    cp -a tests benchmarks pyproject.toml examples "$root/root/src/"
    chroot_run "$root" apt-get update -qq

    if [ -d "$root/root/ego" ]; then  # a reused board: this tree's ego, by the guide's line
        chroot_run "$root" /root/ego/bin/pip uninstall --quiet --yes ego
    fi
    echo "== $arch: $guide's install blocks, as written"
    install_blocks "$guide" | sed 's/\bsudo //g' >"$root/root/install.sh"
    cat "$root/root/install.sh"
    chroot_run "$root" bash -euxo pipefail /root/install.sh

    echo "== $arch: checks"
    cp tools/board_inside.sh "$root/root/"
    chroot_run "$root" bash -euo pipefail /root/board_inside.sh
    echo "== $arch: passed in $(( $(date +%s) - start )) s"
}

umount_all() {
    local root=$1 m
    for m in tmp dev/pts dev proc; do
        mountpoint -q "$root/$m" 2>/dev/null && umount -l "$root/$m"
    done
    return 0
}

status=0
for arch in "${arches[@]}"; do
    # Each board in a subshell: its EXIT trap unmounts it before the next one starts; a
    # board that fails does not stop the other's check, and the status says it failed.
    # (Not under `||`: bash would ignore set -e inside the subshell there.)
    set +e
    (set -e; check_arch "$arch") 2>&1 | tee "$cache/check-$arch.log"
    [ "${PIPESTATUS[0]}" -eq 0 ] || status=1
    set -e
done
exit $status

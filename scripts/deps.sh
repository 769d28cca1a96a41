#!/bin/sh
# Install the Debian packages the build needs, and only those that are missing.
#
#   scripts/deps.sh [EXTRA_PACKAGE...]
#
# Silent and quick when everything is already installed, so `make` can call it
# on every run. When something is missing it runs `apt-get update` once, then
# installs all missing packages in one `apt-get install`. Needs root (or sudo).
#
# Environment:
#   DEPS_LOCK_WAIT_S  seconds to wait for another apt-get/dpkg to finish
#                     (default 900)
#
# Exit status: 0 when every package is installed afterwards, non-zero otherwise.

set -eu

# Host compiler and make for the host build and host tests; the Cortex-M4
# cross toolchain and its C library; CMocka for host tests; QEMU to run target
# images; dpkg-dev for `apt-get source` (scripts/cmocka_src.sh).
# Makefiles pass extra packages for their own targets: cppcheck, python3,
# gcovr (mk/hardening.mk); openocd, stlink-tools for the STM32 bench
# guide's commands (mk/stm32.mk, STM32_BENCH_PACKAGES).
BASE_PACKAGES="gcc make gcc-arm-none-eabi binutils-arm-none-eabi \
libnewlib-arm-none-eabi libcmocka-dev qemu-system-arm dpkg-dev coreutils"

is_installed() {
    status=$(dpkg-query -W -f='${Status}' "$1" 2>/dev/null || true)
    [ "$status" = "install ok installed" ]
}

missing=""
for pkg in $BASE_PACKAGES "$@"; do
    case " $missing " in *" $pkg "*) continue ;; esac
    if ! is_installed "$pkg"; then
        missing="$missing $pkg"
    fi
done

[ -z "$missing" ] && exit 0

if [ "$(id -u)" -eq 0 ]; then
    as_root=""
elif command -v sudo >/dev/null 2>&1; then
    as_root="sudo"
else
    echo "deps.sh: missing packages:$missing; run this script as root" >&2
    exit 1
fi

# Another apt-get or dpkg (an unattended upgrade, a parallel install) holds
# the locks; waiting beats failing with "Could not get lock".
wait_s=${DEPS_LOCK_WAIT_S:-900}
waited=0
while pgrep -x apt-get >/dev/null 2>&1 || pgrep -x dpkg >/dev/null 2>&1; do
    if [ "$waited" -ge "$wait_s" ]; then
        echo "deps.sh: apt-get/dpkg still running after ${wait_s} s" >&2
        exit 1
    fi
    [ "$waited" -eq 0 ] && echo "deps.sh: waiting for another apt-get/dpkg to finish" >&2
    sleep 5
    waited=$((waited + 5))
done

echo "deps.sh: installing:$missing" >&2
lock_opt="-o DPkg::Lock::Timeout=$wait_s"
# shellcheck disable=SC2086 # word splitting of the option and package list is wanted
$as_root apt-get $lock_opt -qq update
# shellcheck disable=SC2086
$as_root env DEBIAN_FRONTEND=noninteractive \
    apt-get $lock_opt -qq -y install $missing >/dev/null

still=""
for pkg in $missing; do
    is_installed "$pkg" || still="$still $pkg"
done
if [ -n "$still" ]; then
    echo "deps.sh: could not install:$still" >&2
    exit 1
fi
exit 0

#!/bin/sh
# Run a Cortex-M4 ELF on QEMU's MPS2 AN386 board and return its exit code.
#
#   scripts/run_m4.sh [-t SECONDS] ELF [ARG ...]
#
# ARGs reach the program as its semihosting command line (SYS_GET_CMDLINE:
# "ELF ARG ...", hal_mps2_get_cmdline()); they may not contain spaces.
# Files the program opens through semihosting are relative to the current
# directory.
#
# Output: the program's semihosting console (hal/mps2/semihost.h) and newlib's
# stdout (test images) go to this script's stdout; newlib's stderr (CMocka's
# failure messages and summary) and QEMU's own messages go to its stderr.
# Without the chardev below QEMU would send the semihosting console to its
# stderr.
# `-icount shift=0` makes virtual time count instructions, so
# hal_mps2_icount_now() is deterministic (hal/mps2/icount.h).
#
# Time limit: -t SECONDS, else $M4_TIMEOUT_S, else 120 s of host time.
#
# Exit status:
#   the program's exit code (main's return value, or hal_mps2_exit()'s
#   status, modulo 256)
#   124  the program did not finish in time (message on stderr)
#   125  usage error, missing ELF, or QEMU not installed
#   other QEMU's own failure (it exits 1 on a bad image, for example)

set -u

timeout_s=${M4_TIMEOUT_S:-600}
if [ "${1:-}" = "-t" ]; then
    if [ $# -lt 2 ]; then
        echo "usage: $0 [-t SECONDS] ELF [ARG ...]" >&2
        exit 125
    fi
    timeout_s=$2
    shift 2
fi
if [ $# -lt 1 ]; then
    echo "usage: $0 [-t SECONDS] ELF [ARG ...]" >&2
    exit 125
fi
elf=$1
shift
# QEMU's option syntax: arguments separated by commas, a literal comma doubled.
semi_args="arg=$(printf '%s' "$elf" | sed 's/,/,,/g')"
for a in "$@"; do
    case $a in
    *" "*)
        echo "run_m4.sh: an argument may not contain spaces: '$a'" >&2
        exit 125
        ;;
    esac
    semi_args="$semi_args,arg=$(printf '%s' "$a" | sed 's/,/,,/g')"
done
if [ ! -f "$elf" ]; then
    echo "run_m4.sh: no such file: $elf" >&2
    exit 125
fi
qemu=${QEMU_SYSTEM_ARM:-qemu-system-arm}
if ! command -v "$qemu" >/dev/null 2>&1; then
    echo "run_m4.sh: $qemu not found (scripts/deps.sh installs qemu-system-arm)" >&2
    exit 125
fi

# -serial none / -monitor none: output only through semihosting, and stdio
# free for the semihosting console's chardev.
# SIGKILL 5 s after SIGTERM in case QEMU ignores the first.
timeout -k 5 "$timeout_s" "$qemu" \
    -M mps2-an386 -nographic -monitor none -serial none \
    -chardev stdio,id=semihost \
    -semihosting-config "enable=on,target=native,chardev=semihost,$semi_args" \
    -icount shift=0 \
    -kernel "$elf" </dev/null
rc=$?

case $rc in
124 | 137)
    echo "run_m4.sh: $elf timed out after ${timeout_s} s" >&2
    exit 124
    ;;
esac
exit "$rc"

#!/bin/sh
# Run the STM32F405 image on QEMU's netduinoplus2 and return its exit code.
#
#   scripts/run_stm32_qemu.sh [-t SECONDS] ELF UART_OUT [ARG ...]
#
# The program's semihosting console goes to stdout (hal/mps2/semihost.h,
# as scripts/run_m4.sh does it), USART1 to the file UART_OUT. ARGs reach
# the program as its semihosting command line. `-icount shift=0`: virtual
# time counts instructions, so timings are the same on every host.
# Time limit: -t SECONDS, else $M4_TIMEOUT_S, else 120 s.
#
# Exit status: the program's (hal_mps2_exit()), 124 on timeout, 125 usage
# error or QEMU missing.

set -u

timeout_s=${M4_TIMEOUT_S:-120}
if [ "${1:-}" = "-t" ]; then
    timeout_s=${2:?}
    shift 2
fi
if [ $# -lt 2 ]; then
    echo "usage: $0 [-t SECONDS] ELF UART_OUT [ARG ...]" >&2
    exit 125
fi
elf=$1
uart=$2
shift 2
[ -f "$elf" ] || { echo "run_stm32_qemu.sh: no such file: $elf" >&2; exit 125; }
semi_args="arg=$(printf '%s' "$elf" | sed 's/,/,,/g')"
for a in "$@"; do
    semi_args="$semi_args,arg=$(printf '%s' "$a" | sed 's/,/,,/g')"
done
qemu=${QEMU_SYSTEM_ARM:-qemu-system-arm}
command -v "$qemu" >/dev/null 2>&1 || { echo "run_stm32_qemu.sh: $qemu not found" >&2; exit 125; }

timeout -k 5 "$timeout_s" "$qemu" \
    -M netduinoplus2 -display none -monitor none -serial "file:$uart" \
    -chardev stdio,id=semihost \
    -semihosting-config "enable=on,target=native,chardev=semihost,$semi_args" \
    -icount shift=0 \
    -kernel "$elf" </dev/null
rc=$?
case $rc in
124 | 137)
    echo "run_stm32_qemu.sh: $elf timed out after ${timeout_s} s" >&2
    exit 124
    ;;
esac
exit "$rc"

#!/bin/sh
# Check that a product ELF links no dynamic memory and no floating point,
# and optionally report its flash and RAM use.
#
#   scripts/check_image.sh [-b|--bench [NAME]] ELF
#
# Fails (exit 1) naming each forbidden symbol the ELF defines or references:
#   malloc free calloc realloc _sbrk and their reentrant _*_r forms
#   __aeabi_f* __aeabi_d*        soft-float helpers of the Arm EABI
#   __addsf3 __muldf3 ... and the other GCC soft-float helpers
#
# With --bench it also prints, for `make bench`,
#   bench: NAME_flash  <text+data>      bytes
#   bench: NAME_ram    <data+bss+stack> bytes
#   bench: NAME_stack  <reserved stack> bytes
# (text, data and bss as Berkeley arm-none-eabi-size counts them; the stack
# section is NOLOAD, so bss includes it). NAME defaults to the ELF's name
# without its directory and .elf suffix.
#
# Environment: M4_NM, M4_SIZE override the tools (default arm-none-eabi-*).
# Exit status: 0 clean, 1 forbidden symbols found, 2 usage or tool error.

set -eu

usage() {
    echo "usage: $0 [-b|--bench [NAME]] ELF" >&2
    exit 2
}

bench=0
name=""
while [ $# -gt 1 ]; do
    case $1 in
    -b | --bench)
        bench=1
        shift
        if [ $# -gt 1 ]; then
            name=$1
            shift
        fi
        ;;
    *) usage ;;
    esac
done
[ $# -eq 1 ] || usage
elf=$1
[ -f "$elf" ] || { echo "check_image.sh: no such file: $elf" >&2; exit 2; }

nm_tool=${M4_NM:-arm-none-eabi-nm}
size_tool=${M4_SIZE:-arm-none-eabi-size}

symbols=$("$nm_tool" "$elf" | awk '{ print $NF }') || exit 2
found=$(printf '%s\n' "$symbols" | grep -E \
    -e '^(malloc|free|calloc|realloc|_sbrk)$' \
    -e '^_(malloc|free|calloc|realloc|sbrk)_r$' \
    -e '^__aeabi_[fd]' \
    -e '^__(add|sub|mul|div|neg|cmp|eq|ne|lt|le|gt|ge|unord)[sdt]f[23]$' \
    -e '^__(fix|fixuns|float|floatun)[a-z]*[sdt]f[a-z]*$' \
    -e '^__(extend|trunc)[sdt]f[sdt]f2$' |
    sort -u | tr '\n' ' ' | sed 's/ $//') || true

status=0
if [ -n "$found" ]; then
    echo "check_image.sh: $elf links forbidden symbols: $found" >&2
    status=1
fi

if [ "$bench" -eq 1 ]; then
    [ -n "$name" ] || name=$(basename "$elf" .elf)
    # Berkeley format, decimal: "text data bss dec hex filename".
    sizes=$("$size_tool" -B -d "$elf" | awk 'NR == 2 { print $1, $2, $3 }')
    # shellcheck disable=SC2086 # split "text data bss" into $1 $2 $3
    set -- $sizes
    [ $# -eq 3 ] || { echo "check_image.sh: cannot read sizes of $elf" >&2; exit 2; }
    stack=$("$size_tool" -A -d "$elf" | awk '$1 == ".stack" { print $2 }')
    echo "bench: ${name}_flash $(($1 + $2)) bytes"
    echo "bench: ${name}_ram $(($2 + $3)) bytes"
    echo "bench: ${name}_stack ${stack:-0} bytes"
fi
exit "$status"

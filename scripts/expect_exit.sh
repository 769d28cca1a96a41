#!/bin/sh
# Run a command, show its output, and check its exit code and output lines.
#
#   scripts/expect_exit.sh CODE OUTFILE [-q] [-l LINE]... -- COMMAND [ARG...]
#
# Saves the command's stdout and stderr, interleaved as written, in OUTFILE
# (and prints them, unless -q: a run that must fail prints its test-failure
# report only into OUTFILE, so that a log reader does not take it for a real
# failure), then fails unless
# the command exited with CODE and OUTFILE has each LINE as a whole line.
# Used by `make -f mk/m4.mk test-m4-selftest` for runs that must fail in a known
# way as well as for those that must pass.

set -u

if [ $# -lt 4 ]; then
    echo "usage: $0 CODE OUTFILE [-l LINE]... -- COMMAND [ARG...]" >&2
    exit 2
fi
want=$1
out=$2
shift 2
quiet=0
lines_file=$(mktemp)
trap 'rm -f "$lines_file"' EXIT
while [ $# -gt 0 ] && [ "$1" != "--" ]; do
    case $1 in
    -q)
        quiet=1
        shift
        ;;
    -l)
        [ $# -ge 2 ] || { echo "expect_exit.sh: -l needs a line" >&2; exit 2; }
        printf '%s\n' "$2" >>"$lines_file"
        shift 2
        ;;
    *)
        echo "expect_exit.sh: unknown option $1" >&2
        exit 2
        ;;
    esac
done
if [ "${1:-}" != "--" ] || [ $# -lt 2 ]; then
    echo "expect_exit.sh: no command" >&2
    exit 2
fi
shift

mkdir -p "$(dirname "$out")"
"$@" >"$out" 2>&1
rc=$?
[ "$quiet" -eq 1 ] || cat "$out"

status=0
if [ "$rc" -ne "$want" ]; then
    echo "expect_exit.sh: FAIL: '$*' exited with $rc, expected $want" >&2
    status=1
fi
while IFS= read -r line; do
    if ! grep -qxF -- "$line" "$out"; then
        echo "expect_exit.sh: FAIL: output of '$*' lacks the line: $line" >&2
        status=1
    fi
done <"$lines_file"
[ "$status" -eq 0 ] && echo "expect_exit.sh: ok: '$*' exited with $rc as expected"
exit "$status"

#!/bin/sh
# Shows that the MISRA check can fail: runs it, exactly as `make misra` does
# (same script, same deviations), over tests/misra/planted_violation.c and
# expects exit status 1 with one finding per line marked "planted: RULE", at
# that line and of that rule, and no other finding.
#
#   tests/misra/planted_test.sh CHECK_COMMAND...
#
# CHECK_COMMAND is the check without its sources, e.g.
#   python3 scripts/misra_check.py --deviations misra/deviations.txt

set -u

src=tests/misra/planted_violation.c
out=${TMPDIR:-/tmp}/misra_planted.$$
trap 'rm -f "$out" "$out.want" "$out.got"' EXIT

"$@" --allow-unused "$src" >"$out" 2>&1
rc=$?
if [ "$rc" -ne 1 ]; then
    cat "$out"
    echo "misra-planted: the check exited $rc on planted violations, expected 1"
    exit 1
fi

# Wanted: "LINE RULE" of each planted marker; got: the same of each finding.
grep -n 'planted: [0-9]' "$src" | sed 's/^\([0-9]*\):.*planted: \([0-9.]*\).*/\1 \2/' | sort >"$out.want"
sed -n "s|^$src:\([0-9]*\):[0-9]*: MISRA C:2012 rule \([0-9.]*\) .*|\1 \2|p" "$out" | sort >"$out.got"
if [ ! -s "$out.want" ] || ! cmp -s "$out.want" "$out.got"; then
    cat "$out"
    echo "misra-planted: findings (line rule) differ from the planted ones:"
    diff "$out.want" "$out.got"
    exit 1
fi
if ! grep -q "^misra: 1 source files, $(wc -l <"$out.want") findings: 0 covered by deviations, $(wc -l <"$out.want") not covered" "$out"; then
    cat "$out"
    echo "misra-planted: unexpected other findings"
    exit 1
fi
echo "misra-planted: the check fails on $src as it should:"
sed 's/^\([0-9]*\) \(.*\)/    line \1: rule \2/' "$out.got"

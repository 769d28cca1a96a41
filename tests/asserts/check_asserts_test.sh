#!/bin/sh
# Shows that the assert rules can fail, and what a failure prints.
#
#   tests/asserts/check_asserts_test.sh DEMO
#
# 1. scripts/check_asserts.py over tests/asserts/planted.c.in exits 1 and
#    reports exactly the lines marked "/* planted", at those lines.
# 2. DEMO (tests/asserts/test_assert_demo.c, built) passes its "pass" group
#    and fails every test of its "fail" group, each printing the values
#    listed below.
# Run from the repository root. Exit status 0 when all of that holds.

set -u

me=check_asserts_test
src=tests/asserts/planted.c.in
demo=${1:?usage: $0 DEMO}
out=${TMPDIR:-/tmp}/check_asserts.$$
trap 'rm -f "$out" "$out.want" "$out.got"' EXIT

fail() {
    cat "$out"
    echo "$me: $*"
    exit 1
}

python3 scripts/check_asserts.py "$src" >"$out" 2>&1
rc=$?
[ "$rc" -eq 1 ] || fail "check_asserts.py exited $rc on planted bare comparisons, expected 1"
grep -n '/\* planted' "$src" | cut -d: -f1 | sort -n >"$out.want"
sed -n "s|^$src:\([0-9]*\): bare comparison: .*|\1|p" "$out" | sort -n >"$out.got"
if [ ! -s "$out.want" ] || ! cmp -s "$out.want" "$out.got"; then
    echo "planted at lines: $(tr '\n' ' ' <"$out.want")"
    echo "reported at lines: $(tr '\n' ' ' <"$out.got")"
    fail "check_asserts.py did not report exactly the planted lines"
fi
echo "$me: check_asserts.py reports the $(wc -l <"$out.want") planted bare comparisons, nothing else"

"$demo" pass >"$out" 2>&1 || fail "$demo pass failed (exit $?)"
"$demo" fail >"$out" 2>&1
rc=$?
[ "$rc" -eq 9 ] || fail "$demo fail exited $rc, expected 9 (one per failing test)"
while IFS= read -r want; do
    grep -qxF "$want" "$out" || fail "$demo fail did not print: $want"
done <<'LINES'
fuel_ul <= limit_ul: fuel_ul = 12, limit_ul = 10
t_us >= 0: t_us = -5, 0 = 0
big < 1U: big = 18446744073709551615, 1U = 1
x > 1.5: x = 1.25, 1.5 = 1.5
0.1 + 0.2 == 0.3: 0.1 + 0.2 = 0.30000000000000004, 0.3 = 0.29999999999999999
|a - 1.0| <= 0.25: a = 1.5, 1.0 = 1, |difference| = 0.5, 0.25 = 0.25
|1.0 - 1.5| < 0.5: 1.0 = 1, 1.5 = 1.5, |difference| = 0.5, 0.5 = 0.5
|r - 0.0| <= 1.0: r = nan, 0.0 = 0, |difference| = nan, 1.0 = 1
r <= 1.0: r = nan, 1.0 = 1
LINES
n=$(grep -c 'error: Failure!' "$out")
[ "$n" -eq 9 ] || fail "$demo fail: $n failures located, expected 9"
echo "$me: the asserts of tests/test_assert.h hold where C's operators do, and print both values when they fail"

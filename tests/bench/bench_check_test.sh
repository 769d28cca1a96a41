#!/bin/sh
# bench_check_test.sh - scripts/bench_check.sh passes figures within their
# targets and fails one over its limit, one missing, and a bad target line.
set -u
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
check=scripts/bench_check.sh
printf '# limits\nsim_12km_hilly_n5 300000  # insn\npfe_mps2_heap 0\n' >"$dir/targets"
printf 'bench: sim_12km_hilly_n5 300000 insn\nbench: pfe_mps2_heap 0 bytes\nother line\n' >"$dir/ok"
printf 'bench: sim_12km_hilly_n5 300001 insn\nbench: pfe_mps2_heap 0 bytes\n' >"$dir/over"
printf 'bench: sim_12km_hilly_n5 1 insn\n' >"$dir/missing"
printf 'sim_12km_hilly_n5 lots\n' >"$dir/bad"
fail=0
expect() { # STATUS PATTERN FILE TARGETS
    sh "$check" "$4" "$3" >"$dir/out" 2>&1
    rc=$?
    if [ "$rc" -ne "$1" ] || ! grep -q "$2" "$dir/out"; then
        echo "bench_check_test: $3: exit $rc (want $1), output:"; cat "$dir/out"; fail=1
    fi
}
expect 0 "all 2 targets met" "$dir/ok" "$dir/targets"
expect 1 "sim_12km_hilly_n5 *300001 > *300000: FAIL" "$dir/over" "$dir/targets"
expect 1 "pfe_mps2_heap *missing from the bench output: FAIL" "$dir/missing" "$dir/targets"
expect 2 "bad:1: expected NAME LIMIT" "$dir/ok" "$dir/bad"
expect 2 "cannot read" "$dir/nothing" "$dir/targets"
[ "$fail" -eq 0 ] && echo "bench_check_test: 5 cases as expected"
exit "$fail"

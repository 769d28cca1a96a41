#!/bin/sh
# The number of trucks swept (thesis chapter 6's missing sweep, and its
# O(N) claim): node and object model over one road for N = FIRST .. LAST,
# each run once under callgrind, counting instructions only inside
# node_sim_run or object_sim_run (as make thesis-bench), with its fuel.
#
#   scripts/n_sweep.sh PLATOON_COMPARE ROAD.csv OUT_DIR [FIRST LAST]
#
# Prints a table (N, node and object fuel, their difference, instructions
# of each, the ratio and the ratio per truck) and writes OUT_DIR/n_sweep.csv
# with the same columns. Exit status 0, 1 when a run fails (its log is
# printed), 2 on bad arguments.
set -u
if [ $# -lt 3 ]; then
    echo "usage: scripts/n_sweep.sh PLATOON_COMPARE ROAD.csv OUT_DIR [FIRST LAST]" >&2
    exit 2
fi
pc=$1
road=$2
out=$3
first=${4:-1}
last=${5:-32}
case "$first$last" in
*[!0-9]*) echo "n_sweep: FIRST and LAST must be whole numbers" >&2; exit 2 ;;
esac
[ -r "$road" ] || { echo "n_sweep: cannot read $road" >&2; exit 2; }
mkdir -p "$out/callgrind" || exit 2
csv=$out/n_sweep.csv
echo "n,node_fuel_l,object_fuel_l,object_pct,node_insn,object_insn,insn_ratio,ratio_per_truck" >"$csv"
echo "N sweep on $(basename "$road"): fuel and instructions (callgrind, inside node_sim_run / object_sim_run)"
printf '%4s %12s %12s %9s %14s %12s %8s %10s\n' N "node [L]" "object [L]" "object %" "node insn" \
    "object insn" ratio "ratio / N"
n=$first
while [ "$n" -le "$last" ]; do
    for m in node object; do
        if ! valgrind --tool=callgrind --callgrind-out-file="$out/callgrind/$m.n$n" \
            --toggle-collect="${m}_sim_run" "$pc" --only "$m" --road "$road" --vehicles "$n" \
            >"$out/callgrind/$m.n$n.out" 2>"$out/callgrind/$m.n$n.log"; then
            cat "$out/callgrind/$m.n$n.out" "$out/callgrind/$m.n$n.log"
            exit 1
        fi
    done
    node_l=$(sed -n 's/.*: fuel \([0-9.]*\) L.*/\1/p' "$out/callgrind/node.n$n.out")
    obj_l=$(sed -n 's/.*: fuel \([0-9.]*\) L.*/\1/p' "$out/callgrind/object.n$n.out")
    node_i=$(awk '/^totals:/ { print $2 }' "$out/callgrind/node.n$n")
    obj_i=$(awk '/^totals:/ { print $2 }' "$out/callgrind/object.n$n")
    if [ -z "$node_l" ] || [ -z "$obj_l" ] || [ -z "$node_i" ] || [ -z "$obj_i" ]; then
        echo "n_sweep: N = $n: no fuel or instruction count (see $out/callgrind/*.n$n.*)" >&2
        exit 1
    fi
    awk -v n="$n" -v a="$node_l" -v b="$obj_l" -v i="$node_i" -v j="$obj_i" -v csv="$csv" 'BEGIN {
        pct = 100 * (b - a) / a; r = i / j;
        printf "%4d %12.4f %12.4f %+9.3f %14d %12d %8.2f %10.3f\n", n, a, b, pct, i, j, r, r / n;
        printf "%d,%.4f,%.4f,%.4f,%d,%d,%.4f,%.4f\n", n, a, b, pct, i, j, r, r / n >> csv }'
    n=$((n + 1))
done
echo "csv: $csv"

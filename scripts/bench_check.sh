#!/bin/sh
# bench_check.sh TARGETS BENCH_OUTPUT - holds `make bench`'s figures
# ("bench: NAME VALUE UNIT" lines) to the limits in TARGETS ("NAME LIMIT",
# '#' starts a comment). Prints one line per target; exits 1 if a figure is
# above its limit or missing, 2 on unreadable files or a bad target line.
set -u
targets=$1
out=$2
[ -r "$targets" ] || { echo "bench_check: cannot read $targets" >&2; exit 2; }
[ -r "$out" ] || { echo "bench_check: cannot read $out" >&2; exit 2; }
awk -v tf="$targets" '
    FNR == NR {
        sub(/#.*/, "")
        if (NF == 0) next
        if (NF != 2 || $2 !~ /^[0-9]+$/) { printf "bench_check: %s:%d: expected NAME LIMIT\n", tf, FNR; bad = 2; next }
        name[++n] = $1; limit[$1] = $2 + 0
        next
    }
    $1 == "bench:" && ($2 in limit) { value[$2] = $3 + 0; seen[$2] = 1 }
    END {
        if (bad) exit bad
        fails = 0
        for (i = 1; i <= n; i++) {
            k = name[i]
            if (!(k in seen)) { printf "bench-target: %-26s missing from the bench output: FAIL\n", k; fails++ }
            else if (value[k] > limit[k]) { printf "bench-target: %-26s %12d > %12d: FAIL\n", k, value[k], limit[k]; fails++ }
            else printf "bench-target: %-26s %12d <= %11d: ok\n", k, value[k], limit[k]
        }
        if (fails) { printf "bench_check: %d of %d targets failed\n", fails, n; exit 1 }
        printf "bench_check: all %d targets met\n", n
    }' "$targets" "$out"

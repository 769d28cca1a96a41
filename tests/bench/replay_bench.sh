#!/bin/sh
# Log parsing throughput of pfe_replay and of can-utils' canplayer, in the
# same run on the same machine (make replay-bench runs it in the vcan VM:
# canplayer needs a kernel with CAN sockets even to write to stdout).
#
#   replay_bench.sh FRAMES MD5 [RUNS]
#
# Generates the benchmark log of FRAMES frames with biglog_gen (this folder)
# and checks that its md5sum is MD5, the host's copy's. Then both programs
# read it with timestamps ignored and write every frame to standard output
# (`-t -I big.log stdout=vcan0`, canplayer's stdout hook): first once each
# into md5sum, which must agree (the same work: the same bytes out), then
# RUNS (default 3) timed runs each with standard output on /dev/null
# (bench_time, the median kept). Prints:
#   bench: log_parse_fps_vm N frames/s          pfe_replay here
#   bench: canplayer_parse_fps_vm N frames/s    canplayer here
#   bench: log_parse_ratio_vs_canplayer R x     canplayer's time / pfe_replay's
# Exit status: 0, 1 on a failure (message on standard output).
set -u
dir=$(cd "$(dirname "$0")" && pwd)
frames=$1
want_md5=$2
runs=${3:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
log=$tmp/big.log

"$dir/biglog_gen" "$frames" >"$log" || { echo "replay_bench: biglog_gen failed"; exit 1; }
got_md5=$(md5sum <"$log" | cut -d' ' -f1)
[ "$got_md5" = "$want_md5" ] ||
    { echo "replay_bench: the log made here ($got_md5) is not the host's ($want_md5)"; exit 1; }

cp_md5=$(canplayer -t -I "$log" stdout=vcan0 | md5sum | cut -d' ' -f1)
rp_md5=$("$dir/pfe_replay" -t --quiet -I "$log" stdout=vcan0 2>/dev/null | md5sum | cut -d' ' -f1)
[ "$cp_md5" = "$rp_md5" ] && [ "$cp_md5" = "$want_md5" ] ||
    { echo "replay_bench: outputs differ: canplayer $cp_md5, pfe_replay $rp_md5, log $want_md5"; exit 1; }

cp_t=$("$dir/bench_time" "$runs" canplayer -t -I "$log" stdout=vcan0 2>"$tmp/err") ||
    { cat "$tmp/err"; exit 1; }
rp_t=$("$dir/bench_time" "$runs" "$dir/pfe_replay" -t --quiet -I "$log" stdout=vcan0 2>"$tmp/err") ||
    { grep -v '^pfe_replay:' "$tmp/err"; exit 1; }
echo "replay_bench: canplayer -t -I big.log stdout=vcan0 > /dev/null: $cp_t"
echo "replay_bench: pfe_replay -t -I big.log stdout=vcan0 > /dev/null: $rp_t"
awk -v n="$frames" -v c="$(echo "$cp_t" | cut -d' ' -f2)" -v r="$(echo "$rp_t" | cut -d' ' -f2)" 'BEGIN {
    printf "bench: log_parse_fps_vm %.0f frames/s\n", n / r
    printf "bench: canplayer_parse_fps_vm %.0f frames/s\n", n / c
    printf "bench: log_parse_ratio_vs_canplayer %.1f x\n", c / r
}'

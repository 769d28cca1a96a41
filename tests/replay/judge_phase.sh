#!/bin/sh
# ecu_check against a module whose tick phase differs from the reference's,
# in the log's time (pfe_ecu_replay), so that it is the same on every machine.
#
# On a real bus the speed sender keeps a schedule of its own and the
# module's 10 ms ticks fall anywhere against the capture's first frame. A
# CCVS1 frame that arrives just before the module's tick is in that tick's
# answer, and in none of the reference's own ticks before the answer's send
# time: under make test-loaded a late canplayer put CCVS1 3 ms before the
# module's LFE1 tick and ecu_check failed a right answer (3.179 %). Here the
# drive's CCVS1 goes out P ms into its 100 ms period (drivegen
# --speed-phase-ms), and another node's DM1 2.5 ms before the drive's first
# frame starts the module's clock but is left out of the capture the judge
# reads, so that the module's ticks fall 7.5 ms into the reference's.
# Every P from 0 to 99 ms must pass; a module with
# another truck's calibration (truck60t.cal) must fail, or the judge proves
# nothing.
#
#   tests/replay/judge_phase.sh OUTDIR HOST_TOOLS_DIR
#
# Exit status 0 when all of it holds.
set -u
out=$1 tools=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"
# The e2e drive (Makefile, E2E_PAYLOAD/drive.log): flat, a vertical curve, 2 %.
road="--segment 600:0 --segment 50:0.5 --segment 50:1 --segment 50:1.5 --segment 750:2 --set-speed-kmh 90"

# judge NAME P [pfe_ecu_replay options...]: the files OUTDIR/NAME.*; prints
# ecu_check's worst rate error, returns ecu_check's exit status (2 when a
# tool failed before it).
judge() {
    n=$1 p=$2
    shift 2
    "$tools/drivegen" $road --speed-phase-ms "$p" --out "$out/$n.drive.log" 2> /dev/null || return 2
    { echo "(1699999999.997500) vcan0 18FECA01#0000000000000000"; cat "$out/$n.drive.log"; } \
        > "$out/$n.log"
    "$tools/pfe_ecu_replay" --log "$out/$n.log" --record "$out/$n.rec.log" "$@" \
        > /dev/null 2>&1 || return 2
    grep -v ' 18FECA01#' "$out/$n.rec.log" > "$out/$n.capture.log"
    "$tools/ecu_check" "$out/$n.capture.log" > "$out/$n.txt"
    rc=$?
    sed -n 's/.*\(worst rate error [0-9.]* %\).*/\1/p' "$out/$n.txt"
    return "$rc"
}

fail=0 passed=0 samples=""
p=0
while [ "$p" -le 99 ]; do
    line=$(judge "phase$p" "$p")
    rc=$?
    if [ "$rc" -eq 0 ]; then
        passed=$((passed + 1))
    else
        echo "judge_phase: CCVS1 at $p ms into its period: ecu_check exit $rc ($line)"
        sed 's/^/  /' "$out/phase$p.txt"
        fail=1
    fi
    case $p in 0 | 44 | 99) samples="$samples; $p ms: $line" ;; esac
    p=$((p + 1))
done
echo "judge_phase: $passed of 100 speed phases pass (${samples#; })"

line=$(judge truck60t 45 --calib "$root/sim_host/data/trucks/truck60t.cal")
rc=$?
if [ "$rc" -eq 1 ]; then
    echo "judge_phase: a module with truck60t.cal fails, as it must ($line)"
else
    echo "judge_phase: a module with truck60t.cal: ecu_check exit $rc, not 1 ($line)"
    fail=1
fi
[ "$fail" -eq 0 ] && echo "judge_phase: PASS" || echo "judge_phase: FAIL"
exit "$fail"

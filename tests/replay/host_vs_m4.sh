#!/bin/sh
# The same logs through the firmware on the host (pfe_ecu_replay) and in the
# Cortex-M4 image under QEMU (pfe_ecu_mps2.elf), both in the log's time:
# their records of the bus must be identical byte for byte, and so must their
# summaries. Then each record is judged:
#   drive.log   ecu_check: LFE1 within 1 %, HRLFC within 0.5 % of the reference
#   faults.log  pfe_faults judge: each input fault handled in time, and
#               pfe_faults must fail on the fault-free record (it can fail)
#   bad.log     a log with bad lines: both refuse it the same way (exit 1,
#               same first bad line named)
#   printed.txt the drive in candump's printed form (-t z, an error frame,
#               -e's detail line): identical records, the drive's frames,
#               judged by ecu_check (times from 0); and the drive's record
#               with a silence of 10^9 s: ecu_check ends
#   truck.txt   a bench's printed log of a truck (two CCVS1 senders, no SSI,
#               the engine's LFE1, 200 unread PGNs): identical records,
#               own-truck rates sent
#   PLATOON_LOG a whole bundled road (5 trucks from PFE_PlatoonConfig, grade
#               previews, sensor noise): identical records, judged by
#               ecu_check, and predictions sent with values
#               (PFE_FuelPrediction, PGN 0xFF03, not "not available")
#
#   tests/replay/host_vs_m4.sh OUTDIR HOST_TOOLS_DIR M4_ELF DRIVE_LOG [PLATOON_LOG]
#
# Exit status 0 when all of it holds.
set -u
out=$1 tools=$2 elf=$3 drive=$4 platoon=${5:-}
root=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"
fail=0

run_both() { # NAME LOG [options...]
    name=$1 log=$2
    shift 2
    "$tools/pfe_ecu_replay" --log "$log" --record "$out/$name.host.log" "$@" \
        > "$out/$name.host.txt" 2> "$out/$name.host.err"
    host_rc=$?
    "$root/scripts/run_m4.sh" "$elf" --log "$log" --record "$out/$name.m4.log" "$@" \
        > "$out/$name.m4.txt" 2> "$out/$name.m4.err"
    m4_rc=$?
    grep '^replay:' "$out/$name.m4.txt" > "$out/$name.m4.summary"
    grep '^replay:' "$out/$name.host.txt" > "$out/$name.host.summary"
    if [ "$host_rc" -ne "$m4_rc" ]; then
        echo "replay $name: exit status host $host_rc, Cortex-M4 $m4_rc"
        fail=1
    elif ! cmp -s "$out/$name.host.log" "$out/$name.m4.log"; then
        echo "replay $name: records differ:"
        cmp "$out/$name.host.log" "$out/$name.m4.log"
        fail=1
    elif ! cmp -s "$out/$name.host.summary" "$out/$name.m4.summary"; then
        echo "replay $name: summaries differ:"
        cat "$out/$name.host.summary" "$out/$name.m4.summary"
        fail=1
    else
        echo "replay $name: host and Cortex-M4 records identical," \
            "$(wc -l < "$out/$name.m4.log") lines, $(wc -c < "$out/$name.m4.log") bytes" \
            "(sha256 $(sha256sum < "$out/$name.m4.log" | cut -c1-16)), exit status $m4_rc"
        grep '^m4:' "$out/$name.m4.txt" | sed "s/^/replay $name: /"
    fi
    return "$m4_rc"
}

run_both drive "$drive" || { echo "replay drive: failed"; cat "$out/drive.m4.txt"; fail=1; }
"$tools/ecu_check" "$out/drive.m4.log" || fail=1

"$tools/pfe_faults" inject "$drive" "$out/faults.log" || fail=1
run_both faults "$out/faults.log" || { echo "replay faults: failed"; fail=1; }
"$tools/pfe_faults" judge "$out/faults.m4.log" || fail=1
# A loaded machine's replay stalls: SSI silent for 60 ms at 29.80 s, just
# before the fault's 2 s silence at 30 s. The judge takes the longest gap
# near the fault, not the first (it took the stall for the fault before).
awk 'NR == 1 { t0 = substr($1, 2, length($1) - 2) + 0 }
     { d = substr($1, 2, length($1) - 2) - t0
       if (($3 ~ /^0CF013/) && (d > 29.80) && (d < 29.86)) next; print }' \
    "$out/faults.m4.log" > "$out/faults_stall.m4.log"
if "$tools/pfe_faults" judge "$out/faults_stall.m4.log" > "$out/faults_stall.txt"; then
    echo "replay: pfe_faults finds the SSI fault behind a 60 ms stall of the replay"
else
    cat "$out/faults_stall.txt"
    echo "replay: pfe_faults took a 60 ms stall of the replay for the SSI fault"
    fail=1
fi
if "$tools/pfe_faults" judge "$out/drive.m4.log" > "$out/faults_on_clean.txt"; then
    echo "replay: pfe_faults passed a record without faults"
    fail=1
else
    echo "replay: pfe_faults fails a record without faults, as it should"
fi

# Bad lines in the middle of a drive: counted, skipped, the first named.
head -n 100 "$drive" > "$out/bad.log"
printf '(1700000001.000000) vcan0 18FEF100#GG\n' >> "$out/bad.log"
printf '(1700000001.000000) vcan0 18FEF100#00112233445566778899\n' >> "$out/bad.log"
tail -n +101 "$drive" | head -n 100 >> "$out/bad.log"
run_both bad "$out/bad.log"
bad_rc=$?
if [ "$bad_rc" -ne 1 ] || ! grep -q 'line 101: bad data' "$out/bad.m4.txt" ||
    ! grep -q 'bad.log:101: bad hex' "$out/bad.host.err" || ! grep -q ' bad 2 ' "$out/bad.m4.summary"; then
    echo "replay bad: expected exit 1 and line 101 named on both (got $bad_rc):"
    cat "$out/bad.m4.txt" "$out/bad.host.err"
    fail=1
else
    echo "replay bad: both name it: $(grep 'bad lines' "$out/bad.m4.txt")"
fi

# The drive as benches record it: candump's printed form, -t z (from the
# first frame), with a comment and the lines -e writes under an error
# frame; the same record on both, and the same frames as the candump log's.
{ echo '# candump -t z -e can0'
  awk 'NR == 50 { print "(000.100000)  vcan0  20000004   [8]  00 04 00 00 00 00 00 00   ERRORFRAME";
                  print "\tcontroller-problem{rx-error-warning}" }
       { t = substr($1, 2, length($1) - 2) - 1700000000; split($3, a, "#"); d = a[2]; s = "";
         for (i = 1; i <= length(d); i += 2) s = s " " substr(d, i, 2);
         printf "(%03d.%06d)  %s  %8s   [%d] %s\n", int(t), (t - int(t)) * 1000000 + 0.5, $2, a[1],
                length(d) / 2, s }' "$drive"; } > "$out/printed.txt"
run_both printed "$out/printed.txt" || { echo "replay printed: failed"; fail=1; }
cut -d' ' -f2- "$out/printed.m4.log" > "$out/printed.frames"
cut -d' ' -f2- "$out/drive.m4.log" > "$out/drive.frames"
if cmp -s "$out/printed.frames" "$out/drive.frames" && grep -q ' not_classic 1 ' "$out/printed.m4.summary"; then
    echo "replay printed: the printed form gives the candump log's record (times from 0)"
else
    echo "replay printed: the record differs from the candump log's"
    cat "$out/printed.m4.summary"
    fail=1
fi
# ecu_check on records it once ticked through for ever: one whose times
# start at 0 (the printed drive's) is judged like the drive's; one with a
# silence of 10^9 s in it (the drive, then the drive again with its clock
# 10^9 s on: a logger whose clock jumped) ends, the silence crossed in one
# jump, whatever its verdict.
if timeout 60 "$tools/ecu_check" "$out/printed.m4.log" > "$out/printed.check.txt"; then
    echo "replay printed: ecu_check on the record from time 0: $(tail -n 1 "$out/printed.check.txt")"
else
    echo "replay printed: ecu_check on the record from time 0 failed or did not end within 60 s:"
    cat "$out/printed.check.txt"
    fail=1
fi
{ cat "$out/drive.m4.log"; sed 's/^(17/(27/' "$out/drive.m4.log"; } > "$out/jump.log"
timeout 60 "$tools/ecu_check" "$out/jump.log" > "$out/jump.check.txt"
rc=$?
if [ "$rc" -le 1 ] && grep -q '1 silence(s) of over 11 s crossed in one jump' "$out/jump.check.txt"; then
    echo "replay jump: ecu_check ended (exit $rc), $(grep 'crossed' "$out/jump.check.txt" | cut -d' ' -f2-)"
else
    echo "replay jump: ecu_check exit $rc (124: did not end within 60 s):"
    cat "$out/jump.check.txt"
    fail=1
fi
# A bench's log as recorded on a truck (tests/host/data/two_senders.txt
# without the module's own frames): printed form, mid-drive, two CCVS1
# senders (one not available), no SSI, the engine's LFE1, 200 PGNs the
# module does not read. Identical on both, and the own-truck estimate
# (PFE_OwnFuel, 18FF058C) sent with values on a road assumed flat.
grep -v '^([0-9.]*)  vcan0  ......8C ' "$root/tests/host/data/two_senders.txt" > "$out/truck.txt"
run_both truck "$out/truck.txt" || { echo "replay truck: failed"; fail=1; }
n_own=$(grep -c ' 18FF058C#' "$out/truck.m4.log")
n_own_valid=$(grep ' 18FF058C#' "$out/truck.m4.log" | grep -vc '#FFFF')
echo "replay truck: $n_own PFE_OwnFuel sent, $n_own_valid with a rate"
[ "$n_own_valid" -gt $((n_own * 3 / 4)) ] || { echo "replay truck: too few own-truck rates"; fail=1; }
if [ -n "$platoon" ]; then
    run_both platoon "$platoon" || { echo "replay platoon: failed"; fail=1; }
    "$tools/ecu_check" "$out/platoon.m4.log" || fail=1
    # PFE_FuelPrediction from the module (18FF038C): PredictedFuel in bytes 1-2.
    n_pred=$(grep -c ' 18FF038C#' "$out/platoon.m4.log")
    n_valid=$(grep ' 18FF038C#' "$out/platoon.m4.log" | grep -vc '#FFFF')
    echo "replay platoon: $n_pred predictions sent, $n_valid with values, e.g." \
        "$(grep ' 18FF038C#' "$out/platoon.m4.log" | grep -v '#FFFF' | sed -n 100p)"
    [ "$n_valid" -gt $((n_pred / 2)) ] || { echo "replay platoon: too few predictions"; fail=1; }
fi
[ "$fail" -eq 0 ] && echo "replay: host and Cortex-M4 agree on every log"
exit "$fail"

#!/bin/sh
# run_report judged on captures made without a bus: the firmware's ECU run
# in simulated time on the first 30 s of the bundled hilly drive
# (tests/host/ecu_offline.c), right and deliberately wrong.
#
#   tests/host/run_report_test.sh RUN_REPORT ECU_OFFLINE HILLY.log OUT_DIR [RUN_REPORT_PLAIN]
#
# A capture as a bench records one on a truck (tests/host/data/
# two_senders.txt, candump's printed form: two CCVS1 senders, one not
# available, no SSI, no platoon configuration, 200 PGNs nobody reads, the
# engine's LFE1 at 1.25 times the module's own-truck rate): a report and a
# plot of what is there, and the module judged against the engine (r 1,
# ratio 0.8); the same with the model identified for the second half
# (ratio 1 there), and as an older capture with the module's LFE1 instead of
# PFE_OwnFuel (the engine's LFE1 never taken for the module's).
#
# RUN_REPORT_PLAIN, a build without sanitizers (whose shadow memory no
# address-space limit allows), runs the capture whose clock jumps by
# 200,000,000 s under `ulimit -v` and `timeout`.
#
# Checks: a right module passes its expectations (exit 0, JUnit without
# failures, CSV, metrics and PNG written), whatever its tick phase; a module
# 2 % wrong fails them (exit 1, JUnit failures naming the quantities; its
# own total (PFE_OwnFuel) reads 2.2 % off: its 0.001 L step on 0.194 L); a bad
# expectation file and a bad capture are refused with file and line (exit 2);
# rates right after gaps in the inputs are left out and counted;
# a quantity that cannot be measured fails its expectation.
# Exit status: the number of failed checks.
set -u
report=$1
offline=$2
hilly=$3
out=$4
plain=${5:-}
rm -rf "$out"
mkdir -p "$out"
failed=0

check() {
    name=$1
    shift
    if "$@"; then
        echo "run_report_test: $name ok"
    else
        echo "run_report_test: $name FAILED"
        failed=$((failed + 1))
    fi
}

# $1 expected exit status, then the command; output in $out/last.out/.err
runs() {
    want=$1
    shift
    "$@" >"$out/last.out" 2>"$out/last.err"
    got=$?
    if [ "$got" -ne "$want" ]; then
        echo "  '$*' exited $got, not $want"
        sed 's/^/  | /' "$out/last.out" "$out/last.err" | tail -n 30
        return 1
    fi
}

has() {
    grep -q -- "$2" "$1" || { echo "  '$2' not in $1:"; sed 's/^/  | /' "$1" | tail -n 30; return 1; }
}

awk '$1 < "(1700000030.000000)"' "$hilly" >"$out/drive30.log"
cat >"$out/accuracy.expect" <<'EOF'
# the fixed-point module against the reference
max_rate_error_pct 1.0
max_platoon_rate_error_pct 1.0     # platoon
total_fuel_error_pct <= 0.5
platoon_fuel_error_pct 0.5
lfe1_frames >= 240
lfe1_not_available 0
distance_km 0.75 2%
EOF

right_module() {
    runs 0 "$offline" "$out/drive30.log" "$out/right.log" || return 1
    runs 0 "$report" "$out/right.log" --out "$out/right/report" --expect "$out/accuracy.expect" \
        --junit "$out/right/junit.xml" || return 1
    has "$out/last.out" "verdict PASS: 7 of 7 expectations met" &&
        has "$out/right/junit.xml" '<testsuite name="run_report" tests="7" failures="0"' &&
        has "$out/right/junit.xml" '<testcase classname="run_report.right.log" name="distance_km"' &&
        has "$out/right/report.csv" '^time_s,speed_kmh,grade_pct,module_rate_l_h,ref_rate_l_h,module_total_l,ref_total_l$' &&
        has "$out/right/report.metrics" '^lfe1_not_available 0$' || return 1
    rows=$(($(wc -l <"$out/right/report.csv") - 1))
    [ "$rows" -ge 290 ] || { echo "  only $rows CSV rows"; return 1; }
    [ "$(head -c 8 "$out/right/report.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
        { echo "  $out/right/report.png is not a PNG"; return 1; }
}

other_phase() {
    runs 0 "$offline" "$out/drive30.log" "$out/phase.log" --phase-us 9700 || return 1
    runs 0 "$report" "$out/phase.log" --out "$out/phase/report" --no-plot \
        --expect "$out/accuracy.expect" || return 1
    has "$out/last.out" "verdict PASS"
}

wrong_module() {
    runs 0 "$offline" "$out/drive30.log" "$out/wrong.log" --scale-fuel 1.02 || return 1
    runs 1 "$report" "$out/wrong.log" --out "$out/wrong/report" --no-plot \
        --expect "$out/accuracy.expect" --junit "$out/wrong/junit.xml" || return 1
    has "$out/last.out" "FAIL  max_rate_error_pct = 2\." &&
        has "$out/last.out" "FAIL  total_fuel_error_pct = 2\.[0-9]" &&
        has "$out/last.out" "pass  distance_km" &&
        has "$out/last.out" "verdict FAIL: 3 of 7 expectations met" &&
        has "$out/wrong/junit.xml" 'tests="7" failures="4"' &&
        has "$out/wrong/junit.xml" '<failure type="expectation" message="platoon_fuel_error_pct = 2\.'
}

# SSI frames missing for 90 ms, and the CCVS1 of 20.0 s sent at 20.2 s, just
# before the one of 20.2 s: three input timing events (SSI 100 ms apart,
# CCVS1 300 ms and 0 ms apart); the rates in the 2 s after each are left out,
# and counted.
input_gap() {
    awk '($1 == "(1700000020.200000)") && ($3 ~ /^0CF013/) { print "(1700000020.200000) vcan0 18FEF100#FF005AFFFFFFFFFF" }
         !(($1 > "(1700000010.000000)") && ($1 < "(1700000010.090000)") && ($3 ~ /^0CF013/)) &&
         !(($1 == "(1700000020.000000)") && ($3 ~ /^18FEF1/)) { print }' \
        "$out/drive30.log" >"$out/gap30.log"
    runs 0 "$offline" "$out/gap30.log" "$out/gap.log" || return 1
    runs 0 "$report" "$out/gap.log" --out "$out/gap/report" --no-plot --expect "$out/accuracy.expect" &&
        has "$out/last.out" "verdict PASS" &&
        has "$out/gap/report.metrics" '^input_timing_events 3$' &&
        has "$out/last.out" "rates not judged: [1-9][0-9]* of 500"
}

# The module's LFE1 and PFE_OwnFuel frames missing from 15.0 to 15.5 s (a
# loop stalled, then catching up, as a capture shows it): two timing events
# of the module's own frames, 500 ms apart against their 100 ms period; the
# rates among them are left out and counted, and the verdict stands.
output_gap() {
    awk '!(($1 > "(1700000015.000000)") && ($1 < "(1700000015.500000)") &&
           ($3 ~ /^18FEF28C#/ || $3 ~ /^18FF058C#/)) { print }' \
        "$out/right.log" >"$out/outgap.log"
    runs 0 "$report" "$out/outgap.log" --out "$out/outgap/report" --no-plot \
        --expect "$out/accuracy.expect" &&
        has "$out/last.out" "verdict PASS" &&
        has "$out/last.out" "among 2 timing events of the module's own frames" &&
        has "$out/last.out" "rates not judged: [1-9][0-9]* of "
}

# The module's PFE_OwnFuel and PFE_PlatoonFuel of 20.0 to 21.0 s sent 80 ms
# late (a loop catching up after a stall sends each tick's right values
# late): judged at the ticks that made them (their 100 ms schedule), the
# rates are right; judged at their send times they were 18 % off.
late_frames() {
    awk '{ t = substr($1, 2, 17) + 0; if (NR == 1) t0 = t; d = t - t0
           if (($3 ~ /^18FF058C#/ || $3 ~ /^18FF038C#/) && (d >= 20.0) && (d < 21.0)) {
               $1 = sprintf("(%.6f)", t + 0.080) } print }' "$out/right.log" |
        sort -s -k1,1 >"$out/late.log"
    runs 0 "$report" "$out/late.log" --out "$out/late/report" --no-plot \
        --expect "$out/accuracy.expect" &&
        has "$out/last.out" "verdict PASS" &&
        has "$out/last.out" "judged at the ticks that made them .*: sent up to 80.0 ms after them"
}

bad_expectations() {
    printf 'max_rate_error_pct 1.0\n\n# fine so far\nfuel_l 1.0\n' >"$out/bad1.expect"
    runs 2 "$report" "$out/right.log" --out "$out/bad/report" --no-plot --expect "$out/bad1.expect" &&
        has "$out/last.err" "bad1.expect:4: unknown quantity 'fuel_l'" || return 1
    printf 'max_rate_error_pct 1.0\ntotal_fuel_l 0x1 1%%\n' >"$out/bad2.expect"
    runs 2 "$report" "$out/right.log" --out "$out/bad/report" --no-plot --expect "$out/bad2.expect" &&
        has "$out/last.err" "bad2.expect:2: bad number '0x1'" || return 1
    printf 'total_fuel_l 1 2 3\n' >"$out/bad3.expect"
    runs 2 "$report" "$out/right.log" --out "$out/bad/report" --no-plot --expect "$out/bad3.expect" &&
        has "$out/last.err" "bad3.expect:1: expected 'NAME VALUE TOLERANCE'" || return 1
    : >"$out/bad4.expect"
    runs 2 "$report" "$out/right.log" --out "$out/bad/report" --no-plot --expect "$out/bad4.expect" &&
        has "$out/last.err" "bad4.expect: no expectations"
}

bad_capture() {
    head -n 4 "$out/right.log" >"$out/bad.log"
    echo "(1700000001.000000) vcan0 18FEF100#FF0G5AFFFFFFFFFF" >>"$out/bad.log"
    runs 2 "$report" "$out/bad.log" --out "$out/bad/report" --no-plot &&
        has "$out/last.err" "bad.log:5: bad hex: 'G' in the data" || return 1
    printf '\0\1\2' >"$out/binary.log"
    runs 2 "$report" "$out/binary.log" --out "$out/bad/report" --no-plot &&
        has "$out/last.err" "binary.log:1: binary content"
}

not_measured() {
    printf 'total_fuel_l 1.0 1%%\n' >"$out/total.expect"
    runs 1 "$report" "$out/drive30.log" --out "$out/silent/report" \
        --expect "$out/total.expect" --junit "$out/silent/junit.xml" &&
        has "$out/last.out" "FAIL  total_fuel_l not measured (no own-truck total (PFE_OwnFuel, HRLFC) from the module)" &&
        has "$out/last.out" "plot:    none" &&
        has "$out/silent/junit.xml" 'failures="1"'
}

# A logger that starts at one time and then gets its clock: 200,000,000 s
# (6.3 years) between two frames. The reference crosses the silence in one
# jump as pfe_ecu_replay does: 400 MB of address space and 60 s suffice
# (ticking across it stored 1.7 GB within 20 s).
time_jump() {
    awk '{ t = substr($1, 2, 17); if (t >= "1700000015.000000") {
               s = substr(t, 1, 10) + 200000000; $1 = "(" s substr(t, 11) ")" } print }' \
        "$out/right.log" >"$out/jump.log"
    runs 0 sh -c "ulimit -v 400000 && exec timeout 60 \"$plain\" \"$out/jump.log\" \
        --out \"$out/jump/report\" --no-plot" || return 1
    has "$out/last.out" "1 silence of over 11 s crossed in one jump" &&
        has "$out/jump/report.metrics" '^gaps_skipped 1$' &&
        has "$out/jump/report.metrics" '^duration_s 2e+08$' &&
        has "$out/jump/report.metrics" '^distance_km 0.74'
}

data=$(cd "$(dirname "$0")" && pwd)/data/two_senders.txt
cat >"$out/engine.expect" <<'EOF'
# tests/host/data/two_senders.txt: the engine's LFE1 is 1.25 x the module's rate
engine_rate_r >= 0.9999
engine_fuel_ratio 0.8 0.05%
engine_fuel_ratio_unidentified 0.8 0.05%
engine_pairs >= 110
lfe1_not_available 0
max_rate_error_pct 1.0
total_fuel_error_pct 0.5
EOF

two_senders() {
    runs 0 "$report" "$data" --out "$out/two/report" --expect "$out/engine.expect" || return 1
    has "$out/last.out" "verdict PASS: 7 of 7" &&
        has "$out/last.out" "against the engine's LFE1 (SA 0x00, 118 frames)" &&
        has "$out/last.out" "default: no PFE_PlatoonConfig" &&
        has "$out/two/report.gp" "no SSI pitch in the capture" &&
        has "$out/two/report.metrics" '^engine_rate_r_identified NA # fewer than 3 pairs with the model identified' &&
        has "$out/two/report.metrics" '^input_timing_events 0$' || return 1
    [ "$(head -c 8 "$out/two/report.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
        { echo "  $out/two/report.png is not a PNG"; return 1; }
}

# The second half with the model identified and the module's rate equal to
# the engine's: ratio 1 there, 0.8 before; overall as a double-precision
# sum over the same pairs computes it here.
identified() {
    awk '$3 == "18FEF200" { e1 = $5; e2 = $6 }
         $3 == "18FF058C" && substr($1, 2, 7) + 0 >= 6.0 && $5 $6 != "FFFF" { $5 = e1; $6 = e2; $11 = "FD" }
         { print }' "$data" >"$out/ident.txt"
    ratio=$(awk 'function hex(s,  v, i) { for (i = 1; i <= length(s); i++) v = v * 16 + index("0123456789ABCDEF", substr(s, i, 1)) - 1; return v }
         function rate(a, b) { return hex(b a) }
         { t = substr($1, 2, length($1) - 2) + 0 }
         $3 == "18FEF200" { if ($5 $6 != "FFFF") { et = t; ev = rate($5, $6); have = 1 } else have = 0 }
         $3 == "18FF058C" { dt = (seen && t - pt <= 0.3) ? t - pt : 0; seen = 1; pt = t
             if ($5 $6 != "FFFF" && have && t - et <= 0.3) { m += rate($5, $6) * dt; e += ev * dt } }
         END { printf "%.6f", m / e }' "$out/ident.txt")
    printf 'engine_fuel_ratio %s 0.0001%%\nengine_fuel_ratio_identified 1.0 0.01%%\n' "$ratio" >"$out/ident.expect"
    printf 'engine_fuel_ratio_unidentified 0.8 0.05%%\nengine_rate_r_identified >= 0.9999\n' >>"$out/ident.expect"
    printf 'engine_rate_r_unidentified >= 0.9999\n' >>"$out/ident.expect"
    runs 0 "$report" "$out/ident.txt" --out "$out/ident/report" --no-plot --expect "$out/ident.expect" &&
        has "$out/last.out" "verdict PASS: 5 of 5" &&
        echo "  overall integrated ratio $ratio (double-precision sum in awk)"
}

# An older capture: the module's estimate in its own LFE1 (SA 0x8C), the
# engine's LFE1 (SA 0x00) beside it. The module is judged on its own LFE1.
older_capture() {
    awk '$3 == "18FF058C" { $3 = "18FEF28C"; for (i = 7; i <= 12; i++) $i = "FF" } { print }' \
        "$data" >"$out/older.txt"
    printf 'engine_fuel_ratio 0.8 0.05%%\nengine_pairs >= 110\n' >"$out/older.expect"
    runs 0 "$report" "$out/older.txt" --out "$out/older/report" --no-plot --expect "$out/older.expect" &&
        has "$out/last.out" "verdict PASS: 2 of 2" &&
        has "$out/last.out" "LFE1 judged: " &&
        has "$out/older/report.metrics" '^engine_fuel_ratio_identified NA # no PFE_OwnFuel from the module: identification unknown'
}

check right_module right_module
check other_phase other_phase
check wrong_module wrong_module
check input_gap input_gap
check output_gap output_gap
check late_frames late_frames
check bad_expectations bad_expectations
check bad_capture bad_capture
check not_measured not_measured
check two_senders two_senders
check identified identified
check older_capture older_capture
if [ -n "$plain" ]; then
    check time_jump time_jump
fi
echo "run_report_test: $failed check(s) failed"
exit "$failed"

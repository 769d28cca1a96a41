#!/bin/sh
# Every host tool that runs the model takes --calib FILE: a bad one
# (unknown key, bad unit, out of range, missing file) is refused with exit
# status 2 and the file and line named; a good one is taken by all of them:
# drivegen drives a 60 t truck (the uphill road), pfe_ecu_replay --calib
# estimates it, and run_report --calib finds the module within 1 % of its
# reference, while run_report with the default calibration (40 t) does not.
#
#   tests/host/truck_cal_tools.sh HOST_TOOLS_DIR TRUCKS_DIR OUTDIR [ROAD.csv]
set -u
tools=$1 trucks=$2 out=$3 road=${4:-sim_host/data/roads/uphill.csv}
mkdir -p "$out"
fail=0
printf 'mass 12 t\nmasss 3 t\n' > "$out/unknown.cal"
printf 'mass 12 lb\n' > "$out/unit.cal"
printf '# heavy\n\nmass 120 t\n' > "$out/range.cal"
# tool, its other arguments (a calibration error must come before any use of them)
check() { # NAME CAL EXPECT TOOL ARGS...
    name=$1 cal=$2 expect=$3
    shift 3
    "$@" --calib "$cal" > "$out/$name.out" 2> "$out/$name.err"
    rc=$?
    if [ "$rc" -ne 2 ] || ! grep -q -- "$expect" "$out/$name.err"; then
        echo "truck-cal: $name: expected exit 2 and '$expect', got $rc: $(cat "$out/$name.err")"
        fail=1
    else
        echo "truck-cal: $name: exit 2, $(head -n 1 "$out/$name.err")"
    fi
}
for t in pfe_ecu_replay pfe_ecu drivegen run_report; do
    case $t in
    pfe_ecu_replay) args="--log /dev/null" ;;
    pfe_ecu) args="--iface vcan-none --nvm $out/nvm.bin" ;;
    drivegen) args="--segment 100:0 --out $out/never.log" ;;
    run_report) args="$out/never.log --no-plot" ;;
    esac
    # shellcheck disable=SC2086
    check "$t-unknown" "$out/unknown.cal" "unknown.cal:2: unknown key 'masss'" "$tools/$t" $args
    # shellcheck disable=SC2086
    check "$t-unit" "$out/unit.cal" "unit.cal:1: mass: unknown unit 'lb' (kg, t)" "$tools/$t" $args
    # shellcheck disable=SC2086
    check "$t-range" "$out/range.cal" "range.cal:3: mass: 120 t is out of range 1000 .. 100000 kg" \
        "$tools/$t" $args
    # shellcheck disable=SC2086
    check "$t-missing" "$out/none.cal" "none.cal: cannot read" "$tools/$t" $args
done

cal=$trucks/truck60t.cal
"$tools/drivegen" --road "$road" --calib "$cal" --out "$out/60t.log" 2> "$out/60t.gen.err" || fail=1
"$tools/pfe_ecu_replay" --log "$out/60t.log" --record "$out/60t.rec" --calib "$cal" > /dev/null || fail=1
cat > "$out/60t.expect" <<'EOF2'
max_rate_error_pct 1.0
total_fuel_error_pct 0.5
EOF2
if "$tools/run_report" "$out/60t.rec" --calib "$cal" --no-plot --out "$out/60t" \
    --expect "$out/60t.expect" > "$out/60t.report" 2>&1; then
    echo "truck-cal: 60 t truck: drivegen, pfe_ecu_replay and run_report with --calib agree:" \
        "$(grep 'largest fuel rate error (LFE1)' "$out/60t.report" | tr -s ' ')"
else
    echo "truck-cal: run_report --calib $cal fails the module:"; cat "$out/60t.report"; fail=1
fi
if "$tools/run_report" "$out/60t.rec" --no-plot --out "$out/60t-default" \
    --expect "$out/60t.expect" > "$out/60t-default.report" 2>&1; then
    echo "truck-cal: run_report without --calib should find the 60 t module off its 40 t reference"
    fail=1
else
    echo "truck-cal: without --calib run_report's 40 t reference is off, as it should be:" \
        "$(grep 'own truck fuel used' "$out/60t-default.report" | tr -s ' ')"
fi
[ "$fail" -eq 0 ] && echo "truck-cal: every tool takes a good calibration file and refuses a bad one"
exit "$fail"

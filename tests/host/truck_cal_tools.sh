#!/bin/sh
# Every host tool that runs the model takes --calib FILE: a good file is
# taken, a bad one (unknown key, bad unit, out of range, missing file) is
# refused with exit status 2 and the file and line named.
#
#   tests/host/truck_cal_tools.sh HOST_TOOLS_DIR TRUCKS_DIR OUTDIR
set -u
tools=$1 trucks=$2 out=$3
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
for t in pfe_ecu_replay pfe_ecu; do
    case $t in
    pfe_ecu_replay) args="--log /dev/null" ;;
    pfe_ecu) args="--iface vcan-none --nvm $out/nvm.bin" ;;
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
[ "$fail" -eq 0 ] && echo "truck-cal: every tool refuses a bad calibration file"
exit "$fail"

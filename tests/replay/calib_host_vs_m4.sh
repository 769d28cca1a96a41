#!/bin/sh
# A truck's calibration on the host (pfe_ecu_replay --calib CAL) and
# compiled into the Cortex-M4 image (make firmware CALIB=CAL, sim_host/tools/cal2c.c):
# the same log gives the same record byte for byte and the same summary;
# and the calibration changes what the module sends (the record differs
# from the default calibration's, on the host and in the default image).
#
#   tests/replay/calib_host_vs_m4.sh OUTDIR HOST_TOOLS_DIR CALIB_ELF DEFAULT_ELF CAL LOG
set -u
out=$1 tools=$2 elf=$3 default_elf=$4 cal=$5 log=$6
root=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"
fail=0
"$tools/pfe_ecu_replay" --log "$log" --record "$out/calib.host.log" --calib "$cal" \
    > "$out/calib.host.txt" 2> "$out/calib.host.err" || { cat "$out/calib.host.err"; fail=1; }
"$root/scripts/run_m4.sh" "$elf" --log "$log" --record "$out/calib.m4.log" \
    > "$out/calib.m4.txt" 2> "$out/calib.m4.err" || { cat "$out/calib.m4.txt" "$out/calib.m4.err"; fail=1; }
"$tools/pfe_ecu_replay" --log "$log" --record "$out/default.host.log" \
    > "$out/default.host.txt" 2> "$out/default.host.err" || fail=1
"$root/scripts/run_m4.sh" "$default_elf" --log "$log" --record "$out/default.m4.log" \
    > "$out/default.m4.txt" 2> "$out/default.m4.err" || fail=1
grep '^replay:' "$out/calib.host.txt" > "$out/calib.host.summary"
grep '^replay:' "$out/calib.m4.txt" > "$out/calib.m4.summary"
if ! cmp -s "$out/calib.host.log" "$out/calib.m4.log"; then
    echo "calib: host --calib and the image built for $cal: records differ:"
    cmp "$out/calib.host.log" "$out/calib.m4.log"
    fail=1
elif ! cmp -s "$out/calib.host.summary" "$out/calib.m4.summary"; then
    echo "calib: summaries differ:"
    cat "$out/calib.host.summary" "$out/calib.m4.summary"
    fail=1
else
    echo "calib: host --calib $cal and its Cortex-M4 image: records identical," \
        "$(wc -l < "$out/calib.m4.log") lines (sha256 $(sha256sum < "$out/calib.m4.log" | cut -c1-16))"
    sed 's/^/calib: /' "$out/calib.m4.summary"
fi
if cmp -s "$out/default.host.log" "$out/calib.host.log" ||
    ! cmp -s "$out/default.host.log" "$out/default.m4.log"; then
    echo "calib: the default calibration's record should differ from $cal's and match the default image's"
    fail=1
else
    echo "calib: the default calibration's record differs (own fuel" \
        "$(sed -n 's/.* own_fuel_ul \([0-9]*\) .*/\1/p' "$out/default.host.txt") uL against" \
        "$(sed -n 's/.* own_fuel_ul \([0-9]*\) .*/\1/p' "$out/calib.host.txt") uL), as it should"
fi
[ "$fail" -eq 0 ] && echo "calib: host and Cortex-M4 agree with the truck's calibration"
exit "$fail"

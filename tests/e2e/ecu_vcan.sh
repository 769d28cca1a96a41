#!/bin/sh
# End to end on vcan0: the host ECU (pfe_ecu) on SocketCAN, fed drives by
# can-utils' canplayer, everything on the bus recorded by candump, then
# judged:
#   drive.log   by ecu_check against the double-precision reference;
#   faults.log  (the same drive with input faults, pfe_faults inject) by
#               pfe_faults judge, allowing 20 ms for the ECU's tick phase and
#               the kernel's timing, which the capture does not show.
#
#   tests/e2e/ecu_vcan.sh   (run from its payload folder, with vcan0 up:
#                            scripts/vcan_vm.sh does it, see the Makefile's test-e2e)
#
# The folder holds pfe_ecu, ecu_check, pfe_faults, drive.log and faults.log.
# Exit status 0 when both verdicts pass and the ECU stopped cleanly on
# SIGTERM both times with its NVM written, else 1.
set -u
dir=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)

# run NAME LOG: the ECU on vcan0 with a fresh NVM, LOG replayed, the bus
# recorded to $tmp/NAME.capture.log.
run() {
    name=$1 log=$2
    candump -r 8388608 -L vcan0 > "$tmp/$name.capture.log" &
    dump=$!
    "$dir/pfe_ecu" --iface vcan0 --nvm "$tmp/$name.nvm" --save-interval-ms 1000 &
    ecu=$!
    sleep 1
    echo "e2e $name: replaying $(wc -l < "$log") frames with canplayer"
    t0=$(date +%s)
    canplayer -I "$log" vcan0=vcan0
    t1=$(date +%s)
    sleep 1.2
    kill -TERM "$ecu"
    wait "$ecu"
    ecu_rc=$?
    kill "$dump"
    wait "$dump" 2>/dev/null
    echo "e2e $name: replay took $((t1 - t0)) s; pfe_ecu exit $ecu_rc;" \
        "$(wc -l < "$tmp/$name.capture.log") frames recorded"
    # The NVM file the ECU left must hold its final total.
    [ -s "$tmp/$name.nvm" ] || { echo "e2e $name: no NVM file written"; return 1; }
    return "$ecu_rc"
}

rc=0
run drive "$dir/drive.log" || rc=1
"$dir/ecu_check" "$tmp/drive.capture.log" || rc=1
run faults "$dir/faults.log" || rc=1
"$dir/pfe_faults" judge "$tmp/faults.capture.log" --slack-ms 20 || rc=1
exit "$rc"

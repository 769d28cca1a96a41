#!/bin/sh
# End to end on vcan0: the host ECU (pfe_ecu) on SocketCAN, fed a drive by
# can-utils' canplayer, everything on the bus recorded by candump, then judged
# by ecu_check against the double-precision reference.
#
#   tests/e2e/ecu_vcan.sh   (run from its payload folder, with vcan0 up:
#                            scripts/vcan_vm.sh does it, see the Makefile's e2e-test)
#
# The folder holds pfe_ecu, ecu_check and drive.log. Exit status: ecu_check's,
# or 1 when the ECU did not stop cleanly on SIGTERM.
set -u
dir=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
candump -L vcan0 > "$tmp/capture.log" &
dump=$!
"$dir/pfe_ecu" --iface vcan0 --nvm "$tmp/nvm.bin" --save-interval-ms 1000 &
ecu=$!
sleep 1
echo "e2e: replaying $(wc -l < "$dir/drive.log") frames with canplayer"
t0=$(date +%s)
canplayer -I "$dir/drive.log" vcan0=vcan0
t1=$(date +%s)
sleep 1.2
kill -TERM "$ecu"
wait "$ecu"
ecu_rc=$?
kill "$dump"
wait "$dump" 2>/dev/null
echo "e2e: replay took $((t1 - t0)) s; pfe_ecu exit $ecu_rc; $(wc -l < "$tmp/capture.log") frames recorded"
# The NVM file the ECU left must hold its final total.
[ -s "$tmp/nvm.bin" ] || { echo "e2e: no NVM file written"; exit 1; }
"$dir/ecu_check" "$tmp/capture.log"
rc=$?
[ "$ecu_rc" -eq 0 ] || rc=1
exit "$rc"

#!/bin/sh
# Bus faults in a real kernel (vcan0): the host ECU (pfe_ecu) fed the e2e
# drive by pfe_replay, everything on the bus recorded by candump, while
#   at  8 s  vcan0 is taken down for 2 s, then up again;
#   at 16 s  a flood: cangen sends 100,000 frames of an unrelated 11-bit id
#            (0x123) as fast as it can;
#   at 24 s  a second node claims the module's address 0x8C with a NAME that
#            wins arbitration (J1939-81 Address Claimed, NAME 1).
# Judged from the capture (decoded by pfe_decode) and the tools' summaries:
#   - the replayer reports the frames it could not send while the bus was
#     down, and the module the frames it could not send (PFE_Status
#     TxFramesDropped, its stop line);
#   - after the bus is back the module's fuel rate is valid again within 2 s;
#   - through the flood the module keeps its 10 ms tick: no gap of more than
#     300 ms between its LFE1 frames (sent every 100 ms), its tick overruns
#     as PFE_Status reports them;
#   - after the conflicting claim the module claims another address in
#     128..247 (it is arbitrary-address capable) and sends from there, and
#     no more from 0x8C.
#
#   tests/e2e/bus_faults.sh   (from its payload folder, vcan0 up: scripts/vcan_vm.sh)
#
# The folder holds pfe_ecu, pfe_replay, pfe_decode, pfe.dbc and drive.log.
# Exit status 0 when every check holds, else 1.
set -u
dir=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
fail=0
check() { # NAME CONDITION-RESULT(0/1) DETAIL
    if [ "$2" -eq 0 ]; then echo "bus_faults: $1: ok ($3)"; else echo "bus_faults: $1: FAILED ($3)"; fail=1; fi
}

# candump leaves when its interface goes down: start it again until stopped.
# It records all but the flood's id (0x123: an inverted filter), so that the
# flood cannot overflow its socket and hide the module's frames; a second
# candump counts the flood.
(while :; do candump -r 8388608 -L vcan0,123~7FF 2>>"$tmp/candump.err"; sleep 0.05; done) >"$tmp/cap.log" &
dump=$!
"$dir/pfe_ecu" --iface vcan0 --nvm "$tmp/nvm.bin" --save-interval-ms 1000 2>"$tmp/ecu.err" &
ecu=$!
sleep 1
t0=$(date +%s)
"$dir/pfe_replay" --quiet -I "$dir/drive.log" --end 32 vcan0=vcan0 2>"$tmp/replay.err" &
replay=$!
sleep 8
ip link set vcan0 down
sleep 2
ip link set vcan0 up
sleep 6
candump -r 8388608 -L vcan0,123:7FF >"$tmp/flood.log" 2>/dev/null &
fdump=$!
cangen vcan0 -g 0 -I 123 -L 8 -n 100000 2>/dev/null
sleep 0.5
kill "$fdump" 2>/dev/null
sleep 2
cansend vcan0 18EEFF8C#0100000000000000
wait "$replay"
replay_rc=$?
sleep 1.5
kill -TERM "$ecu"
wait "$ecu"
ecu_rc=$?
kill "$dump" 2>/dev/null
sleep 0.2
pkill candump 2>/dev/null
t1=$(date +%s)
echo "bus_faults: $((t1 - t0)) s of driving; pfe_replay exit $replay_rc; pfe_ecu exit $ecu_rc"
cat "$tmp/replay.err" "$tmp/ecu.err"

# ------------------------------------------------------------------ judging

"$dir/pfe_decode" --dbc "$dir/pfe.dbc" --skip-errors "$tmp/cap.log" >"$tmp/dec.txt" 2>/dev/null
start=$(awk 'NR == 1 { print $1; exit }' "$tmp/dec.txt")
# rel: seconds since the first frame
rel() { awk -v s="$start" '{ printf "%.3f", $1 - s }'; }

# 1. Down: the replayer's and the module's dropped frames.
dropped=$(sed -n 's/.*(\([0-9][0-9]*\) with the interface down).*/\1/p' "$tmp/replay.err" | head -n 1)
[ "${dropped:-0}" -gt 0 ]
check "bus down: the replayer counts what it could not send" $? "${dropped:-0} frames dropped with the interface down"
tx_dropped=$(grep 'PFE_Status' "$tmp/dec.txt" | sed -n 's/.*TxFramesDropped=\([0-9]*\).*/\1/p' | sort -n | tail -n 1)
[ "${tx_dropped:-0}" -gt 0 ]
check "bus down: PFE_Status reports the module's unsent frames" $? "TxFramesDropped up to ${tx_dropped:-0}"

# 2. Recovery: the first valid LFE1 of the module after the bus came back
#    (the first module frame after the gap in the capture).
back=$(awk -v s="$start" '{ t = $1 - s; if (prev != "" && t - prev > 1.0) { print t; exit } prev = t }' "$tmp/dec.txt")
rec=$(awk -v s="$start" -v b="${back:-1e9}" '/ 18FEF28C / { t = $1 - s; if (t >= b && $0 !~ /=NA/) { print t; exit } }' "$tmp/dec.txt")
[ -n "$rec" ] && [ -n "$back" ] && awk -v a="$rec" -v b="$back" 'BEGIN { exit !(a - b <= 2.0) }'
check "bus back: valid fuel rate again within 2 s" $? "bus back at ${back:-?} s, valid LFE1 at ${rec:-never} s"

# 3. Flood: LFE1 keeps its 100 ms period; the status's tick overruns.
flood=$(grep -c ' 123#' "$tmp/flood.log")
gap=$(awk -v s="$start" '/ 18FEF28C / { t = $1 - s; if (t > 15.0 && t < 23.0) { if (p != "" && t - p > g) g = t - p; p = t } }
      END { printf "%.3f", g }' "$tmp/dec.txt")
awk -v g="$gap" 'BEGIN { exit !(g > 0 && g <= 0.3) }'
check "flood: the module keeps sending LFE1 every 100 ms" $? "100000 flood frames sent, $flood seen by a candump of them, longest LFE1 gap $gap s"
overruns=$(grep 'PFE_Status' "$tmp/dec.txt" | sed -n 's/.*TickOverruns=\([0-9]*\).*/\1/p' | sort -n | tail -n 1)
echo "bus_faults: PFE_Status TickOverruns up to ${overruns:-0}, RxFramesDropped up to" \
    "$(grep 'PFE_Status' "$tmp/dec.txt" | sed -n 's/.*RxFramesDropped=\([0-9]*\).*/\1/p' | sort -n | tail -n 1)"

# 4. Address conflict: a new claim from 128..247, then frames from there only.
tc=$(tr -d '()' <"$tmp/cap.log" | awk '$3 == "18EEFF8C#0100000000000000" { print $1; exit }')
claim=$(awk -v tc="${tc:-1e18}" '$1 > tc && $3 ~ /^18EEFF/ && $3 != "18EEFF8C" { print $3; exit }' "$tmp/dec.txt")
new_sa=$(printf '%d' "0x$(echo "${claim:-18EEFF00}" | cut -c7-8)")
late_8c=$(awk -v tc="${tc:-1e18}" '$1 > tc + 0.5 && $3 ~ /8C$/ { n++ } END { print n + 0 }' "$tmp/dec.txt")
late_new=$(awk -v tc="${tc:-1e18}" -v id="$(echo "${claim:-X}" | cut -c7-8)" '$1 > tc && $3 ~ ("^18FEF2" id "$") { n++ } END { print n + 0 }' "$tmp/dec.txt")
[ -n "$claim" ] && [ "$new_sa" -ge 128 ] && [ "$new_sa" -le 247 ] && [ "$late_8c" -eq 0 ] && [ "$late_new" -gt 0 ]
check "address conflict: the module yields 0x8C and claims another" $? \
    "claimed ${claim:-nothing} (address $new_sa); afterwards $late_new LFE1 from it, $late_8c frames from 0x8C"

[ "$replay_rc" -eq 0 ] || [ "$replay_rc" -eq 4 ] || { echo "bus_faults: pfe_replay exit $replay_rc"; fail=1; }
[ "$ecu_rc" -eq 0 ] || { echo "bus_faults: pfe_ecu did not stop cleanly"; fail=1; }
exit "$fail"

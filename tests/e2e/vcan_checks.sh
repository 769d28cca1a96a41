#!/bin/sh
# Every vcan check in one run: the SocketCAN backend's guard and conformance
# tests, then can-utils round trips on the interface $1 (default vcan0).
set -u
dir=$(cd "$(dirname "$0")" && pwd)
ifc=${1:-vcan0}
failed=0
tmp=$(mktemp -d)

check() {
    name=$1
    shift
    echo "== vcan: $name"
    "$@"
    rc=$?
    if [ "$rc" -eq 0 ]; then
        echo "vcan: $name ok"
    else
        echo "vcan: $name FAILED (exit $rc)"
        failed=$((failed + 1))
    fi
}

# Waits until process $1 (a candump) has a receive filter matching PATTERN
# $2 on the interface (/proc/net/can lists every one), so that no frame is
# sent before it listens. Fails if the process ends first.
wait_listening() {
    for _ in $(seq 100); do
        grep -q "$2" /proc/net/can/rcvlist_* 2>/dev/null && return 0
        kill -0 "$1" 2>/dev/null || { echo "candump ended early"; return 1; }
        sleep 0.05
    done
    echo "no CAN socket matching '$2' after 5 s"
    kill "$1"
    return 1
}

# $1: candump's output; $2: the expected lines without timestamps.
same_frames() {
    got=$(cut -d' ' -f2- "$1")
    if [ "$got" != "$2" ]; then
        echo "candump got:"
        cat "$1"
        echo "expected:"
        echo "$2"
        return 1
    fi
}

# cansend -> candump, candump keeping only PGN 65265 (CCVS1) from any
# source at any priority.
cansend_candump() {
    candump -L -n 3 -T 60000 "$ifc,18FEF100:03FFFF00" >"$tmp/dump1" &
    pid=$!
    wait_listening "$pid" 03ffff00 || return 1
    cansend "$ifc" 18FEF117#0011223344556677 &&
        cansend "$ifc" 18FEF200#01 &&
        cansend "$ifc" 0CFEF100#A1B2 &&
        cansend "$ifc" 123#DEADBEEF &&
        cansend "$ifc" 18FEF1FE# || { kill "$pid"; return 1; }
    wait "$pid" || return 1
    same_frames "$tmp/dump1" "$ifc 18FEF117#0011223344556677
$ifc 0CFEF100#A1B2
$ifc 18FEF1FE#"
}

# canplayer -> candump: a log replayed with its own pacing comes back as is.
canplayer_candump() {
    printf '%s\n' "(1700000000.000000) $ifc 18FEF100#00C0160000000000" \
        "(1700000000.010000) $ifc 0CF01313#E87D" \
        "(1700000000.020000) $ifc 7FF#" >"$tmp/in.log"
    candump -L -n 3 -T 60000 "$ifc,7FF:7FF,0CF01313:1FFFFFFF,18FEF100:1FFFFFFF" >"$tmp/dump2" &
    pid=$!
    wait_listening "$pid" 1fffffff || return 1
    canplayer -I "$tmp/in.log" || { kill "$pid"; return 1; }
    wait "$pid" || return 1
    same_frames "$tmp/dump2" "$ifc 18FEF100#00C0160000000000
$ifc 0CF01313#E87D
$ifc 7FF#"
}

# cangen -> candump: 50 random frames, all of them received.
cangen_candump() {
    candump -L -n 50 -T 60000 "$ifc,0:0" >"$tmp/dump3" &
    pid=$!
    wait_listening "$pid" "$ifc  *000  *00000000" || return 1
    cangen "$ifc" -n 50 -g 1 || { kill "$pid"; return 1; }
    wait "$pid" || return 1
    n=$(wc -l <"$tmp/dump3")
    [ "$n" -eq 50 ] || { echo "candump got $n frames of 50"; return 1; }
}

check test_guard "$dir/test_guard" "$ifc"
check test_hal_socketcan "$dir/test_hal_socketcan" "$ifc"
if [ -x "$dir/san/test_guard" ]; then
    check test_guard_asan_ubsan "$dir/san/test_guard" "$ifc"
    check test_hal_socketcan_asan_ubsan "$dir/san/test_hal_socketcan" "$ifc"
fi
check cansend_candump cansend_candump
check canplayer_candump canplayer_candump
check cangen_candump cangen_candump
rm -rf "$tmp"
echo "vcan: $failed check(s) failed"
exit "$failed"

#!/bin/sh
# pfe_record against can-utils' candump -L on the same traffic, in a VM
# with vcan0 and vcan1 (scripts/vcan_vm.sh; see test-record-vm in mk/run.mk).
# Both take the kernel's receive timestamp of the same frame, so their logs
# must be the same, byte for byte.
#
#   tests/e2e/record_vs_candump.sh   (from its payload folder, with pfe_record)
#
# Checks:
#   every_kind   vcan0 (CAN FD MTU): 11- and 29-bit data frames, remote
#                frames with and without a DLC, CAN FD with and without
#                bit-rate switch, error frames, cangen's random mix
#   any          'any' on vcan0 and vcan1 at once
#   drops        a recorder with a small receive buffer (--rcvbuf 65536,
#                about 80 frames) held stopped while 3000 frames arrive
#                reports the frames the kernel dropped: recorded + dropped
#                = 3000 (with its default 8 MiB none would drop)
# Exit status: the number of failed checks.
set -u
dir=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
failed=0

check() {
    name=$1
    shift
    echo "== record: $name"
    if "$@"; then
        echo "record: $name ok"
    else
        echo "record: $name FAILED"
        failed=$((failed + 1))
    fi
}

# Starts candump and pfe_record on $1 (one word); waits until pfe_record
# says it listens, and as long again for candump, started first. candump
# gets error frames through its filter syntax (every id, every error class):
# its -e cannot go with -L.
start_both() {
    candump -r 8388608 -L "$1,0:0,#FFFFFFFF" >"$tmp/candump.log" 2>"$tmp/candump.err" &
    cd_pid=$!
    "$dir/pfe_record" -o "$tmp/record.log" "$1" 2>"$tmp/record.err" &
    pr_pid=$!
    for _ in $(seq 100); do
        grep -q '^pfe_record: recording' "$tmp/record.err" && break
        sleep 0.05
    done
    sleep 0.5
}

stop_both() {
    sleep 0.3
    kill -INT "$cd_pid" "$pr_pid"
    wait "$cd_pid"
    cd_rc=$?
    wait "$pr_pid"
    pr_rc=$?
    [ "$cd_rc" -eq 0 ] || { echo "candump exit $cd_rc:"; cat "$tmp/candump.err"; return 1; }
    cat "$tmp/record.err"
    [ "$pr_rc" -eq 0 ] || { echo "pfe_record exit $pr_rc"; return 1; }
}

same_logs() {
    n=$(wc -l <"$tmp/candump.log")
    if cmp -s "$tmp/candump.log" "$tmp/record.log"; then
        echo "same $n lines; kinds: $(cut -d' ' -f3 "$tmp/record.log" |
            sed -e 's/^[23][0-9A-F]\{7\}#.*/error/' -e 's/^[0-9A-F]*#R.*/remote/' \
                -e 's/^[0-9A-F]*##.*/fd/' -e 's/^[0-9A-F]*#.*/data/' | sort | uniq -c | tr -s ' \n' ' ')"
        [ "$n" -ge "$1" ] || { echo "only $n lines, expected at least $1"; return 1; }
        return 0
    fi
    echo "candump and pfe_record differ:"
    diff "$tmp/candump.log" "$tmp/record.log" | head -n 20
    return 1
}

every_kind() {
    ip link set vcan0 down && ip link set vcan0 mtu 72 && ip link set vcan0 up || return 1
    start_both vcan0
    cansend vcan0 123#DEADBEEF &&
        cansend vcan0 7FF# &&
        cansend vcan0 18FEF100#FF005AFFFFFFFFFF &&
        cansend vcan0 123#R &&
        cansend vcan0 123#R5 &&
        cansend vcan0 1ABCDEF0#R8 &&
        cansend vcan0 321##0 &&
        cansend vcan0 321##1112233445566778899AABBCC &&
        cansend vcan0 12345678##30011223344556677889900112233445566778899001122334455667788990011223344556677889900112233445566778899001122334455667788 &&
        cansend vcan0 20000004#0004000000000000 &&
        cansend vcan0 20000100#0000000000000000 || { stop_both; return 1; }
    cangen vcan0 -m -n 400 -g 1 || { stop_both; return 1; }
    stop_both || return 1
    grep -q '^([0-9]\{10\}\.[0-9]\{6\}) vcan0 20000004#0004000000000000$' "$tmp/record.log" ||
        { echo "no error frame recorded"; return 1; }
    same_logs 411
}

any() {
    start_both any
    cangen vcan0 -e -n 100 -g 1 &
    g1=$!
    cangen vcan1 -n 100 -g 1 || { stop_both; return 1; }
    wait "$g1"
    stop_both || return 1
    grep -q ' vcan1 ' "$tmp/record.log" && grep -q ' vcan0 ' "$tmp/record.log" ||
        { echo "not both interfaces recorded"; return 1; }
    same_logs 200
}

drops() {
    "$dir/pfe_record" --rcvbuf 65536 -o "$tmp/drops.log" vcan1 2>"$tmp/drops.err" &
    pid=$!
    sleep 0.5
    kill -STOP "$pid"
    cangen vcan1 -n 3000 -g 0 -p 10
    kill -CONT "$pid"
    sleep 0.5
    kill -TERM "$pid"
    wait "$pid"
    rc=$?
    cat "$tmp/drops.err"
    [ "$rc" -eq 0 ] || return 1
    n=$(wc -l <"$tmp/drops.log")
    d=$(sed -n 's/^pfe_record: \([0-9]*\) frames recorded, \([0-9]*\) dropped.*/\2/p' "$tmp/drops.err")
    r=$(sed -n 's/^pfe_record: \([0-9]*\) frames recorded, \([0-9]*\) dropped.*/\1/p' "$tmp/drops.err")
    echo "recorded $r (log has $n lines), dropped $d, of 3000"
    [ "$r" = "$n" ] && [ "${d:-0}" -gt 0 ] && [ $((r + d)) -eq 3000 ]
}

check every_kind every_kind
check any any
check drops drops
rm -rf "$tmp"
echo "record: $failed check(s) failed"
exit "$failed"

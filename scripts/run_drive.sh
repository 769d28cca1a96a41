#!/bin/sh
# make run: the module (build/host/pfe_ecu) on a virtual CAN bus fed a drive
# log, everything on the bus recorded, then judged against the reference.
#
# On the host (what `make run` calls):
#
#   scripts/run_drive.sh --payload DIR --out DIR [--expect FILE] [--junit FILE]
#                        [--timeout S] [-- RUN_REPORT_OPTION...]
#
#   The payload folder holds pfe_ecu and pfe_record (linked with -static:
#   the VM has no C library), drive.log (the drive to replay) and a copy of
#   this script. scripts/vcan_vm.sh runs the bus part below with vcan0 up:
#   natively where this machine can have a vcan0, else in Debian's kernel
#   under QEMU (the capture then comes back through the VM's output,
#   gzip + base64 between two marker lines). Then build/host/run_report
#   judges OUT/capture.log: summary on stdout, OUT/report.{csv,metrics,gp,png},
#   and with --expect the verdict (--junit: a JUnit XML report too).
#   Exit status: run_report's (0 pass, 1 an expectation not met, 2 bad
#   input); 3 when the bus part failed (the ECU, the recorder or the replay
#   did not run or stop cleanly); vcan_vm.sh's 124/125 for a VM that timed
#   out or did not start.
#
# On the bus (inside the VM, or natively):
#
#   run_drive.sh --bus DRIVE.log CAPTURE.log
#
#   Starts the recorder on vcan0 (pfe_record, kernel timestamps) and, once it
#   listens, the ECU (fresh NVM file); after 1 s replays DRIVE.log in real
#   time; 1.5 s after the last frame stops the ECU (SIGTERM, final save),
#   then the recorder. Prints what each did.
set -u

me=run_drive.sh
here=$(cd "$(dirname "$0")" && pwd)

# The replayer, the one place where the drive is sent: sim_host/tools/pfe_replay
# (static, in the payload folder) with the log's timestamps as pacing; it
# ends with its summary (frames sent, dropped, lateness). can-utils'
# canplayer takes the same arguments: REPLAY_CMD="canplayer -I".
REPLAY_CMD="$here/pfe_replay --quiet -I"

# ------------------------------------------------------------------ bus part

bus_part() {
    drive=$1
    capture=$2
    tmp=$(mktemp -d)
    mkdir -p "$(dirname "$capture")"
    failed=0

    "$here/pfe_record" -o "$capture" vcan0 2>"$tmp/record.err" &
    rec=$!
    for _ in $(seq 100); do
        grep -q '^pfe_record: recording' "$tmp/record.err" && break
        kill -0 "$rec" 2>/dev/null || break
        sleep 0.05
    done
    if ! grep -q '^pfe_record: recording' "$tmp/record.err"; then
        echo "$me: the recorder did not start:"
        cat "$tmp/record.err"
        kill "$rec" 2>/dev/null
        return 3
    fi

    "$here/pfe_ecu" --iface vcan0 --nvm "$tmp/nvm.bin" --save-interval-ms 1000 &
    ecu=$!
    sleep 1
    echo "$me: replaying $(wc -l <"$drive") frames ($drive) with $REPLAY_CMD"
    t0=$(date +%s)
    # shellcheck disable=SC2086 # REPLAY_CMD is a command and its options
    $REPLAY_CMD "$drive" vcan0=vcan0
    replay_rc=$?
    t1=$(date +%s)
    [ "$replay_rc" -eq 0 ] || { echo "$me: replay failed (exit $replay_rc)"; failed=1; }
    sleep 1.5
    kill -TERM "$ecu"
    wait "$ecu"
    ecu_rc=$?
    [ "$ecu_rc" -eq 0 ] || { echo "$me: pfe_ecu did not stop cleanly (exit $ecu_rc)"; failed=1; }
    sleep 0.2
    kill -TERM "$rec"
    wait "$rec"
    rec_rc=$?
    cat "$tmp/record.err"
    [ "$rec_rc" -eq 0 ] || { echo "$me: pfe_record failed (exit $rec_rc)"; failed=1; }
    echo "$me: replay took $((t1 - t0)) s; $(wc -l <"$capture") frames recorded"
    if [ "${VCAN_VM:-0}" = 1 ]; then
        # The VM's files die with it: the capture goes out on its output.
        echo "@@capture-begin@@"
        gzip -c "$capture" | base64
        echo "@@capture-end@@"
    fi
    rm -rf "$tmp"
    [ "$failed" -eq 0 ] || return 3
    return 0
}

# ------------------------------------------------------------------ host part

usage() {
    echo "usage: $0 --payload DIR --out DIR [--expect FILE] [--junit FILE] [--timeout S] [-- RUN_REPORT_OPTION...]" >&2
    echo "       $0 --bus DRIVE.log CAPTURE.log" >&2
    exit 2
}

if [ "${1:-}" = --bus ]; then
    [ $# -eq 3 ] || usage
    bus_part "$2" "$3"
    exit $?
fi

payload=""
out=""
expect=""
junit=""
timeout_s=600
while [ $# -gt 0 ]; do
    case $1 in
    --payload) [ $# -ge 2 ] || usage; payload=$2; shift 2 ;;
    --out) [ $# -ge 2 ] || usage; out=$2; shift 2 ;;
    --expect) [ $# -ge 2 ] || usage; expect=$2; shift 2 ;;
    --junit) [ $# -ge 2 ] || usage; junit=$2; shift 2 ;;
    --timeout) [ $# -ge 2 ] || usage; timeout_s=$2; shift 2 ;;
    --) shift; break ;;
    *) usage ;;
    esac
done
[ -n "$payload" ] && [ -n "$out" ] || usage
for f in pfe_ecu pfe_record drive.log run_drive.sh; do
    [ -e "$payload/$f" ] || { echo "$me: $payload/$f is missing" >&2; exit 2; }
done
repo=$(cd "$here/.." && pwd)
report_tool=$repo/build/host/run_report
[ -x "$report_tool" ] || report_tool=${RUN_REPORT:-run_report}
payload=$(cd "$payload" && pwd)
mkdir -p "$out"
out=$(cd "$out" && pwd)
capture=$out/capture.log
rm -f "$capture" "$out/bus.out"

# The bus part's output to the terminal as it comes, without the capture's
# encoded copy; all of it to bus.out.
t0=$(date +%s)
{
    "$repo/scripts/vcan_vm.sh" --time --timeout "$timeout_s" --payload "$payload" -- \
        sh "$payload/run_drive.sh" --bus "$payload/drive.log" "$capture" 2>&1
    echo "@@bus-exit $?@@"
} | tee "$out/bus.out" | sed '/^@@capture-begin@@/,/^@@capture-end@@/d; /^@@bus-exit/d'
bus_rc=$(sed -n 's/^@@bus-exit \([0-9]*\)@@$/\1/p' "$out/bus.out")
t1=$(date +%s)
echo "$me: bus part took $((t1 - t0)) s, exit ${bus_rc:-?}"
if grep -q '^@@capture-begin@@' "$out/bus.out"; then
    sed -n '/^@@capture-begin@@/,/^@@capture-end@@/p' "$out/bus.out" | sed '1d;$d' |
        base64 -d | gzip -dc >"$capture" || { echo "$me: the capture did not come back whole" >&2; exit 3; }
fi
case ${bus_rc:-x} in
0) ;;
124 | 125) exit "$bus_rc" ;;
*) echo "$me: the bus part failed (exit ${bus_rc:-?})" >&2; exit 3 ;;
esac
[ -s "$capture" ] || { echo "$me: no capture at $capture" >&2; exit 3; }
echo "$me: capture $capture ($(wc -l <"$capture") frames)"
echo

set -- "$capture" --out "$out/report" "$@"
[ -n "$expect" ] && set -- "$@" --expect "$expect"
[ -n "$junit" ] && set -- "$@" --junit "$junit"
"$report_tool" "$@"

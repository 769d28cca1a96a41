#!/bin/sh
# pfe_replay on vcan: round trips, other formats, pacing against canplayer,
# the real-bus guard. Runs from its payload folder on a machine with vcan0
# and vcan1 up (scripts/vcan_vm.sh; `make test-replay-vcan`).
#
#   replay_vcan.sh
#
# The folder holds pfe_replay, lateness_check, slcan_run (static programs),
# drive.log (the e2e drive, a candump log) and logs/ (the committed logs of
# sim_host/data/logs, maybe none). can-utils (candump, canplayer, cangen,
# log2asc) come with the VM.
#
# Checks, each printed "replay: NAME ok" or "replay: NAME FAILED":
#   round trip (must-show 2): each log goes pfe_replay -> vcan -> candump -L
#     and comes back with the same frames in the same order (ids, FD flags
#     and data, compared as text with the log's, timestamps aside): the
#     drive, each log of logs/, and logs that candump itself wrote of cangen
#     traffic (11-bit, 29-bit, remote frames on vcan0; cangen -m's mix of
#     CAN FD, BRS, ESI, remote, 29-bit on vcan1 with MTU 72)
#   formats (must-show 3): the drive as Vector ASC (written by can-utils'
#     log2asc) and as candump's printed output (-t a and -t z, recorded while
#     the drive was replayed) replays to the same frames as its candump log
#   pacing (must-show 4): the drive's first 15 s in real time, by pfe_replay
#     (its default pacing) and by canplayer side by side, three rounds, each
#     recorded by candump -L: lateness of the kernel's receive timestamps
#     against the log's schedule (lateness_check), p99 and max printed;
#     pfe_replay's p99 over canplayer's in the median round must be at most
#     1, or at most the widest ratio of two control rounds of canplayer
#     against itself in the same run where that is wider (what the machine's
#     scheduling alone does to two equal replayers), and each of its runs
#     last the slice's 15 s (not less; not more than 1.5 s more, or 1 s more
#     than canplayer's run where that is longer)
#   guard (must-show 6): lo, and an slcan interface on a pseudo-terminal,
#     refused without --allow-real-bus: exit 2, the message, nothing sent
# Exit status: the number of failed checks.
set -u
dir=$(cd "$(dirname "$0")" && pwd)
rp=$dir/pfe_replay
tmp=$(mktemp -d)
failed=0
SPEED=10      # round trips: ten times as fast as logged
LOG_SPEED=20  # the bundled logs (8 to 9 minutes of driving each): twenty times
SLICE_S=15    # pacing: seconds of the drive in real time
DRAIN_S=60    # a receiver's time to read its queue once the sender has ended

check() {
    name=$1
    shift
    echo "== replay: $name"
    "$@"
    rc=$?
    if [ "$rc" -eq 0 ]; then
        echo "replay: $name ok"
    else
        echo "replay: $name FAILED (exit $rc)"
        failed=$((failed + 1))
    fi
}

# Waits until interface $2 has at least $3 receivers that take every frame
# (candump without a filter registers can_id 000 mask 00000000 in
# /proc/net/can/rcvlist_all), so that nothing is sent before they listen.
# Fails if process $1 ends first.
wait_listening() {
    for _ in $(seq 200); do
        receivers=$(grep -c "$2  *000  *00000000" /proc/net/can/rcvlist_all 2>/dev/null)
        [ "${receivers:-0}" -ge "$3" ] && return 0
        kill -0 "$1" 2>/dev/null || { echo "candump ended early"; return 1; }
        sleep 0.05
    done
    echo "fewer than $3 receivers on $2 after 10 s"
    return 1
}

# True while process $1 runs (a zombie, ended but not yet waited for, does
# not count).
alive() {
    [ -r "/proc/$1/stat" ] && ! sed 's/^.*) //' "/proc/$1/stat" 2>/dev/null | grep -q '^Z'
}

# Waits for candump $1 (started with -n $2, writing $3) once the sender has
# ended. Every frame it will get is then queued at its socket, so it ends as
# soon as it has read them; a loaded machine gets DRAIN_S seconds for that.
# There is no no-frame timeout (candump -T): a sender slow to start on a
# busy machine (parsing a large log) must not make the receiver give up
# first. Returns candump's exit status, or 1 (and says so) when it had to
# be stopped, with the count of what it wrote.
await_dump() {
    for _ in $(seq $((DRAIN_S * 20))); do
        alive "$1" || { wait "$1"; return $?; }
        sleep 0.05
    done
    kill "$1" 2>/dev/null
    wait "$1" 2>/dev/null
    echo "candump: $(grep -c '^ *(' "$3") of $2 frames when stopped, $DRAIN_S s after the sender ended"
    return 1
}

# The frames of a candump log as text: field 3, upper case, no '.'.
frames_of() {
    grep '^ *(' "$1" | awk '{ f = toupper($3); gsub(/\./, "", f); print f }'
}

# $1 expected candump log, $2 captured candump log
same_frames() {
    frames_of "$1" >"$tmp/want.txt"
    frames_of "$2" >"$tmp/got.txt"
    if ! cmp -s "$tmp/want.txt" "$tmp/got.txt"; then
        echo "frames differ: $(wc -l <"$tmp/want.txt") expected, $(wc -l <"$tmp/got.txt") received; first differences:"
        diff "$tmp/want.txt" "$tmp/got.txt" | head -n 10
        return 1
    fi
    echo "$(wc -l <"$tmp/got.txt") frames, the same, in the same order"
}

# Replays LOG ($1, any format) onto interface $2 with pfe_replay options
# $4..., while candump -L records $3 frames into $tmp/cap.log. Every
# interface of the log goes to $2.
replay_capture() {
    log=$1
    ifc=$2
    n=$3
    shift 3
    # candump asks for 8 MiB of receive buffer (about 10,000 frames, so a
    # busy machine does not make it drop) and reports what the kernel still
    # dropped (-d: DROPCOUNT lines, taken out of the log below).
    candump -r 8388608 -d -L -n "$n" "$ifc" >"$tmp/cap.raw" &
    pid=$!
    wait_listening "$pid" "$ifc" 1 || return 1
    # shellcheck disable=SC2046 # one assignment per interface
    "$rp" --quiet -I "$log" "$@" $(sed -n 's/^ *([^)]*) *\([^ ]*\) .*/\1/p' "$log" | sort -u |
        sed "s/^/$ifc=/") 2>"$tmp/rp_summary.txt" || { cat "$tmp/rp_summary.txt"; kill "$pid"; return 1; }
    cd_rc=0
    await_dump "$pid" "$n" "$tmp/cap.raw" || cd_rc=$?
    grep -v '^DROPCOUNT' "$tmp/cap.raw" >"$tmp/cap.log"
    # candump -d: "DROPCOUNT: dropped N CAN frame(s) on 'IF' socket (total drops T)"
    rx_drops=$(sed -n 's/.*total drops \([0-9]*\).*/\1/p' "$tmp/cap.raw" | tail -n 1)
    rx_drops=${rx_drops:-0}
    sent=$(sed -n 's/^pfe_replay: \([0-9]*\) sent.*/\1/p' "$tmp/rp_summary.txt")
    tx_drops=$(sed -n 's/.* \([0-9]*\) dropped.*/\1/p' "$tmp/rp_summary.txt" | head -n 1)
    got=$(wc -l <"$tmp/cap.log")
    echo "by side: pfe_replay sent ${sent:-?} of $n, dropped ${tx_drops:-?} (transmit queue);" \
        "candump received $got, the kernel dropped $rx_drops at its socket;" \
        "unexplained $((n - ${tx_drops:-0} - rx_drops - got))"
    # A round trip is for identical frames: a frame lost at either side
    # leaves nothing to compare it with, so it fails, saying where it went.
    [ "$cd_rc" -eq 0 ] || { echo "candump: exit $cd_rc ($got of $n frames)"; return 1; }
    [ "$rx_drops" -eq 0 ] || { echo "candump's socket dropped $rx_drops frames (receive buffer full)"; return 1; }
    [ "${tx_drops:-0}" -eq 0 ] || { echo "pfe_replay dropped $tx_drops frames (transmit queue full)"; return 1; }
}

# Round trip of candump log $1 on interface $2 (at speed $3, default SPEED).
round_trip() {
    n=$(grep -c '^ *(' "$1")
    replay_capture "$1" "$2" "$n" --speed "${3:-$SPEED}" || return 1
    echo "$(basename "$1"): $n frames"
    same_frames "$1" "$tmp/cap.log"
}

# ---------------------------------------------------------------- the drive, three recordings

# The drive replayed once, recorded three ways at the same time: the
# candump log (round trip), and candump's printed output with -t a and -t z
# (the same drive in the printed format, for the next checks).
drive_three_ways() {
    n=$(grep -c '^ *(' "$dir/drive.log")
    candump -r 8388608 -L -n "$n" vcan0 >"$tmp/drive_cap.log" &
    p1=$!
    candump -r 8388608 -t a -n "$n" vcan0 >"$tmp/drive_a.txt" &
    p2=$!
    candump -r 8388608 -t z -n "$n" vcan0 >"$tmp/drive_z.txt" &
    p3=$!
    wait_listening "$p1" vcan0 3 || return 1
    "$rp" -I "$dir/drive.log" --speed "$SPEED" --quiet || return 1
    await_dump "$p1" "$n" "$tmp/drive_cap.log" && await_dump "$p2" "$n" "$tmp/drive_a.txt" &&
        await_dump "$p3" "$n" "$tmp/drive_z.txt" || { echo "a candump failed"; return 1; }
    echo "drive.log: $n frames, $(tr -d '()' <"$dir/drive.log" | awk 'NR == 1 { t0 = $1 } END { printf "%.1f", $1 - t0 }') s of log, replayed at $SPEED x"
    same_frames "$dir/drive.log" "$tmp/drive_cap.log" || return 1
    echo "printed output, e.g.: $(sed -n 2p "$tmp/drive_a.txt")"
}

# Replays the drive in format $1 (file $2, mapped from its interface) and
# checks the frames against the drive's candump log. The recordings are of
# the drive replayed $SPEED times as fast: they replay at their own pace.
drive_format() {
    n=$(grep -c '^ *(' "$dir/drive.log")
    replay_capture "$2" vcan0 "$n" || return 1
    same_frames "$dir/drive.log" "$tmp/cap.log"
}

# The ASC: what can-utils' log2asc writes of the recorded drive.
drive_asc() {
    log2asc -I "$tmp/drive_cap.log" vcan0 >"$tmp/drive.asc" || return 1
    echo "ASC by log2asc, e.g.: $(sed -n 5p "$tmp/drive.asc")"
    n=$(grep -c '^ *(' "$dir/drive.log")
    candump -r 8388608 -L -n "$n" vcan0 >"$tmp/cap.log" &
    pid=$!
    wait_listening "$pid" vcan0 1 || return 1
    "$rp" --quiet -I "$tmp/drive.asc" vcan0=can0 || { kill "$pid"; return 1; }
    await_dump "$pid" "$n" "$tmp/cap.log" || return 1
    same_frames "$dir/drive.log" "$tmp/cap.log"
}

# ---------------------------------------------------------------- logs candump wrote of cangen

cangen_log() {
    candump -r 8388608 -L -n 300 vcan0 >"$tmp/cangen.log" &
    pid=$!
    wait_listening "$pid" vcan0 1 || return 1
    cangen vcan0 -n 100 -g 1 && cangen vcan0 -n 100 -g 1 -e && cangen vcan0 -n 100 -g 1 -R ||
        { kill "$pid"; return 1; }
    await_dump "$pid" 300 "$tmp/cangen.log" || return 1
    echo "candump wrote $(wc -l <"$tmp/cangen.log") frames of cangen, e.g. $(sed -n 250p "$tmp/cangen.log")"
    round_trip "$tmp/cangen.log" vcan0
}

cangen_fd_log() {
    ip link set dev vcan1 down && ip link set dev vcan1 mtu 72 && ip link set dev vcan1 up ||
        { echo "cannot give vcan1 the CAN FD MTU"; return 1; }
    candump -r 8388608 -L -n 200 vcan1 >"$tmp/cangen_fd.log" &
    pid=$!
    wait_listening "$pid" vcan1 1 || return 1
    cangen vcan1 -n 200 -g 1 -m || { kill "$pid"; return 1; }
    await_dump "$pid" 200 "$tmp/cangen_fd.log" || return 1
    echo "candump wrote $(grep -c '##' "$tmp/cangen_fd.log") CAN FD frames and $(grep -c '#R' "$tmp/cangen_fd.log") remote frames of 200, e.g. $(grep '##' "$tmp/cangen_fd.log" | head -n 1)"
    round_trip "$tmp/cangen_fd.log" vcan1
}

# ---------------------------------------------------------------- pacing

# p99 and max of a lateness_check line
p99_of() { sed -n 's/.* p99 \([0-9]*\) us max \([0-9]*\) us.*/\1/p' "$1"; }
max_of() { sed -n 's/.* p99 \([0-9]*\) us max \([0-9]*\) us.*/\2/p' "$1"; }
uptime_cs() { awk '{ printf "%d\n", $1 * 100 }' /proc/uptime; }

# One round: pfe_replay (its default pacing) on vcan0 and canplayer on
# vcan1 replay the slice side by side, at the same time, each recorded by its
# own candump -L: the stalls of this machine (QEMU without KVM, a shared
# host) then hit both alike, which one after the other they would not.
# With $2 "control" a second canplayer takes pfe_replay's place: two copies
# of one program side by side, which measures how far apart this machine's
# scheduling alone puts two equal replayers (the VM has one CPU, so the two
# senders take turns at every frame).
# lateness_check's lines in $tmp/late_{first,canplayer}_$1.txt, the first
# sender's wall time (hundredths of a second) in $tmp/dur_$1.txt, the two
# p99s appended to $tmp/pace_p99.txt or $tmp/control_p99.txt.
pace_round() {
    r=$1
    mode=${2:-pfe}
    candump -r 8388608 -L -n "$n" vcan0 >"$tmp/pace_rp_$r.log" &
    c1=$!
    candump -r 8388608 -L -n "$n" vcan1 >"$tmp/pace_cp_$r.log" &
    c2=$!
    wait_listening "$c1" vcan0 1 || return 1
    wait_listening "$c2" vcan1 1 || return 1
    t0=$(uptime_cs)
    if [ "$mode" = control ]; then
        ( canplayer -I "$tmp/slice.log" vcan0=vcan0 2>"$tmp/summary_$r.txt"; echo $? >"$tmp/rc_rp_$r" ) &
    else
        ( "$rp" --quiet -I "$tmp/slice.log" 2>"$tmp/summary_$r.txt"; echo $? >"$tmp/rc_rp_$r" ) &
    fi
    p1=$!
    ( canplayer -I "$tmp/slice.log" vcan1=vcan0; rc=$?; echo $(($(uptime_cs) - t0)) >"$tmp/dur_cp_$r.txt";
      exit "$rc" ) &
    p2=$!
    wait "$p1"
    echo $(($(uptime_cs) - t0)) >"$tmp/dur_$r.txt"
    wait "$p2" || { echo "canplayer: exit $?"; return 1; }
    [ "$(cat "$tmp/rc_rp_$r")" -eq 0 ] || { cat "$tmp/summary_$r.txt"; return 1; }
    await_dump "$c1" "$n" "$tmp/pace_rp_$r.log" || { echo "candump vcan0 failed"; return 1; }
    await_dump "$c2" "$n" "$tmp/pace_cp_$r.log" || { echo "candump vcan1 failed"; return 1; }
    "$dir/lateness_check" "$tmp/slice.log" "$tmp/pace_rp_$r.log" >"$tmp/late_first_$r.txt" || return 1
    "$dir/lateness_check" "$tmp/slice.log" "$tmp/pace_cp_$r.log" >"$tmp/late_canplayer_$r.txt" || return 1
    a=$(p99_of "$tmp/late_first_$r.txt")
    b=$(p99_of "$tmp/late_canplayer_$r.txt")
    ratio=$(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.2f", a / b }')
    if [ "$mode" = control ]; then
        echo "control round $r: canplayer on vcan0 p99 $a us max $(max_of "$tmp/late_first_$r.txt") us;" \
            "canplayer on vcan1 p99 $b us max $(max_of "$tmp/late_canplayer_$r.txt") us; ratio $ratio"
        echo "$a $b" >>"$tmp/control_p99.txt"
        return 0
    fi
    echo "round $r: pfe_replay p99 $a us max $(max_of "$tmp/late_first_$r.txt") us;" \
        "canplayer p99 $b us max $(max_of "$tmp/late_canplayer_$r.txt") us;" \
        "ratio $ratio;" \
        "pfe_replay's own view: $(grep lateness "$tmp/summary_$r.txt" | cut -d' ' -f2-);" \
        "run $(cat "$tmp/dur_$r.txt")0 ms, canplayer's $(cat "$tmp/dur_cp_$r.txt")0 ms"
    echo "$a $b" >>"$tmp/pace_p99.txt"
}

# Three rounds of pfe_replay against canplayer in this one VM run, and two
# control rounds of canplayer against itself between them. pfe_replay must
# pace at least as well as canplayer: its p99 lateness over canplayer's in
# the median round at most 1, or, where this machine puts two copies of
# canplayer further apart than that, at most the control rounds' widest
# ratio (larger over smaller p99: what scheduling alone does to two equal
# replayers in this run). No absolute time: this machine's jitter is not the
# replayer's. Each pfe_replay run must also last the slice's length (a
# replayer sending early, late by whole frames or at the wrong speed would
# not).
pacing() {
    "$rp" --dry-run -t --end "$SLICE_S" -I "$dir/drive.log" >"$tmp/slice.log" 2>/dev/null || return 1
    n=$(wc -l <"$tmp/slice.log")
    echo "the drive's first $SLICE_S s: $n frames, in real time, pfe_replay and canplayer side by side, 3 rounds, and canplayer against itself, 2 control rounds:"
    : >"$tmp/pace_p99.txt"
    : >"$tmp/control_p99.txt"
    for r in 1 c1 2 c2 3; do
        case $r in
            c*) pace_round "$r" control || return 1; continue ;;
        esac
        pace_round "$r" || return 1
        # Not before the slice's length (a replayer sending early or too
        # fast), and not later than 1.5 s after it or 1 s after canplayer,
        # whichever is later (a stalled machine delays both alike).
        dur=$(cat "$tmp/dur_$r.txt")
        dur_cp=$(cat "$tmp/dur_cp_$r.txt")
        late_cs=$((SLICE_S * 100 + 150))
        [ $((dur_cp + 100)) -le "$late_cs" ] || late_cs=$((dur_cp + 100))
        [ "$dur" -ge $((SLICE_S * 100 - 10)) ] && [ "$dur" -le "$late_cs" ] ||
            { echo "round $r: pfe_replay took ${dur}0 ms for ${SLICE_S} s of log (canplayer ${dur_cp}0 ms)"; return 1; }
    done
    wins=$(awk '$1 <= $2 { w++ } END { print w + 0 }' "$tmp/pace_p99.txt")
    median=$(awk '{ print $1 / $2 }' "$tmp/pace_p99.txt" | sort -n | sed -n 2p)
    spread=$(awk '{ q = ($1 > $2) ? $1 / $2 : $2 / $1; if (q > m) m = q } END { printf "%.6g\n", m }' "$tmp/control_p99.txt")
    limit=$(awk -v s="$spread" 'BEGIN { printf "%.6g\n", (s > 1) ? s : 1 }')
    echo "pacing: pfe_replay's p99 at most canplayer's in $wins of 3 rounds; median ratio $median;" \
        "canplayer against itself at most $spread apart; so the median ratio must be <= $limit"
    awk -v m="$median" -v l="$limit" 'BEGIN { exit !(m <= l) }'
}

# ---------------------------------------------------------------- the real-bus guard

# $1 expected status, $2 text of the message, then the command
refused() {
    want=$1
    text=$2
    shift 2
    "$@" >"$tmp/guard_out.txt" 2>"$tmp/guard_err.txt"
    rc=$?
    cat "$tmp/guard_err.txt"
    [ "$rc" -eq "$want" ] || { echo "exit $rc, $want expected"; return 1; }
    grep -qF "$text" "$tmp/guard_err.txt" || { echo "no '$text' in the message"; return 1; }
    [ ! -s "$tmp/guard_out.txt" ] || { echo "it wrote output"; return 1; }
}

guard_lo() {
    refused 2 "refusing to send on lo: it is not a CAN interface" \
        "$rp" -I "$dir/drive.log" lo=vcan0 || return 1
    printf '%s\n' '(1700000000.000000) lo 123#01' >"$tmp/lo.log"
    refused 2 "refusing to send on lo" "$rp" -I "$tmp/lo.log"
}

# The slcan interface exists only while slcan_run runs the command; nothing
# is ever sent to it (refused before the socket is opened).
guard_slcan() {
    # shellcheck disable=SC2016 # $1 and $2 are for the inner shell
    slcan_out=$("$dir/slcan_run" sh -c 'echo "$1: type $(cat /sys/class/net/$1/type)";
        "$2" -I "$3" "$1=vcan0"; echo "exit $?"' sh {} "$rp" "$dir/drive.log" 2>&1)
    rc=$?
    echo "$slcan_out"
    [ "$rc" -eq 0 ] || { echo "slcan_run: exit $rc (77: no slcan in this kernel)"; return 1; }
    echo "$slcan_out" | grep -q "refusing to send on [^:]*: it is a real CAN bus, not a virtual one" ||
        { echo "no refusal"; return 1; }
    echo "$slcan_out" | grep -q "^exit 2$" || { echo "exit status not 2"; return 1; }
}

check "round trip: drive.log, and the drive as candump output" drive_three_ways
for log in "$dir"/logs/*.log; do
    [ -f "$log" ] || continue
    check "round trip: logs/$(basename "$log") at $LOG_SPEED x" round_trip "$log" vcan0 "$LOG_SPEED"
done
check "round trip: candump log of cangen (11-bit, 29-bit, remote)" cangen_log
check "round trip: candump log of cangen -m (CAN FD, BRS, ESI, remote) on vcan1" cangen_fd_log
check "the drive as ASC (log2asc) replays to the drive's frames" drive_asc
check "the drive as candump -t a output replays to the drive's frames" drive_format printed "$tmp/drive_a.txt"
check "the drive as candump -t z output replays to the drive's frames" drive_format printed "$tmp/drive_z.txt"
check "pacing: pfe_replay and canplayer, $SLICE_S s in real time" pacing
check "guard: lo refused" guard_lo
check "guard: slcan refused" guard_slcan
rm -rf "$tmp"
echo "replay: $failed check(s) failed"
exit "$failed"

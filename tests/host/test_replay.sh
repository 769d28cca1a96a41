#!/bin/sh
# pfe_replay on this machine, without CAN: what needs no socket. The dry run
# and the stdout= assignment (each frame written as a candump log line),
# Vector ASC written by can-utils' log2asc, candump's printed output,
# filters, start and end, loops, pacing, every exit status, and the
# real-bus guard on lo (which classifies interfaces through rtnetlink, so it
# works on a kernel without CAN). What needs vcan is tests/e2e/replay_vcan.sh.
#
#   tests/host/test_replay.sh PFE_REPLAY DRIVE_LOG [PFE_ECU_REPLAY PFE_ECU]
#
# With PFE_ECU_REPLAY and PFE_ECU, also what those say about their inputs:
# the firmware replayed over the drive as candump's printed output (-t z,
# -t A) and as ASC gives the record the candump log gives; a directory, a
# bad line (file, line, reason), printed output without timestamps; and
# pfe_ecu's interface checks (an empty name, no such interface, lo which is
# not CAN; a real CAN bus needs the VM, tests/e2e/replay_vcan.sh's slcan).
#
# Exit status: 0 when every check passes, 1 otherwise (each failure printed).
set -u
rp=$1
drive=$2
ecu_replay=${3:-}
ecu=${4:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0

ok() { echo "test_replay: $1 ok"; }
bad() {
    echo "test_replay: $1 FAILED"
    failed=$((failed + 1))
}
# $1 name, $2 expected exit status, $3 text the standard error must hold,
# then the command
expect_exit() {
    name=$1
    want=$2
    text=$3
    shift 3
    "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    if [ "$rc" -eq "$want" ] && grep -qF -- "$text" "$tmp/err"; then
        ok "$name (exit $rc)"
    else
        bad "$name: exit $rc ($want expected), standard error:"
        cat "$tmp/err"
    fi
}
frames() { cut -d' ' -f3 "$1"; }

[ -s "$drive" ] || { echo "test_replay: no drive log $drive"; exit 1; }
n_drive=$(wc -l <"$drive")

# Dry run and stdout=, timestamps ignored: the drive log, byte for byte.
"$rp" --dry-run -t -I "$drive" >"$tmp/dry.log" 2>"$tmp/err"
cmp -s "$tmp/dry.log" "$drive" && ok "dry run rewrites the drive log unchanged" || bad "dry run"
"$rp" -t -I "$drive" stdout=vcan0 >"$tmp/stdout.log" 2>/dev/null
cmp -s "$tmp/stdout.log" "$drive" && ok "stdout=vcan0" || bad "stdout=vcan0"
"$rp" -t stdout=vcan0 <"$drive" >"$tmp/stdin.log" 2>/dev/null
cmp -s "$tmp/stdin.log" "$drive" && ok "standard input" || bad "standard input"
grep -q "0 sent, $n_drive written to stdout, 0 skipped, 0 dropped (0 with the interface down), 0 parse errors" "$tmp/err" &&
    ok "summary counts" || { bad "summary counts:"; cat "$tmp/err"; }

# Vector ASC as can-utils' log2asc writes it (plain, -4 decimals, CANFD lines
# for classic frames, CR LF): the same frames; channel 1 is can0.
if command -v log2asc >/dev/null 2>&1; then
    for opts in "" "-f" "-n" "-4"; do
        # shellcheck disable=SC2086 # no option or one
        log2asc $opts -I "$drive" vcan0 >"$tmp/drive.asc" 2>/dev/null
        "$rp" --dry-run -t -I "$tmp/drive.asc" >"$tmp/asc.log" 2>"$tmp/err"
        if [ "$(frames "$tmp/asc.log" | md5sum)" = "$(frames "$drive" | md5sum)" ] &&
            [ "$(cut -d' ' -f2 "$tmp/asc.log" | sort -u)" = can0 ]; then
            ok "log2asc $opts: the same $(wc -l <"$tmp/asc.log") frames"
        else
            bad "log2asc $opts"
            head -n 3 "$tmp/err"
        fi
    done
    # times from the start: the drive's second 10 ms after its first
    log2asc -I "$drive" vcan0 >"$tmp/drive.asc" 2>/dev/null
    "$rp" --dry-run -t -I "$tmp/drive.asc" vcan0=can0 >"$tmp/asc.log" 2>/dev/null
    # every frame at its time since the drive's first, on vcan0
    awk 'NR == 1 { t0 = substr($1, 2) + 0 }
         { printf "(%017.6f) vcan0\n", substr($1, 2) - t0 }' "$drive" >"$tmp/want_times"
    cut -d' ' -f1-2 "$tmp/asc.log" >"$tmp/asc_times"
    cmp -s "$tmp/want_times" "$tmp/asc_times" &&
        ok "ASC times from the start, can0 mapped to vcan0" ||
        { bad "ASC times:"; diff "$tmp/want_times" "$tmp/asc_times" | head -n 5; }
else
    bad "log2asc (can-utils) not installed"
fi

# candump's printed output (-t a, the 2020.11 layout) converts to the log.
printf '%s\n' ' (1700000000.000000)  vcan0  18FEF100   [8]  FF 00 5A FF FF FF FF FF' \
    ' (1700000000.010000)  vcan0       123   [2]  0A 0B' \
    ' (1700000000.020000)  vcan0       123   [4]  remote request' >"$tmp/printed.txt"
"$rp" --dry-run -t -I "$tmp/printed.txt" >"$tmp/printed.log" 2>/dev/null
printf '%s\n' '(1700000000.000000) vcan0 18FEF100#FF005AFFFFFFFFFF' \
    '(1700000000.010000) vcan0 123#0A0B' '(1700000000.020000) vcan0 123#R4' >"$tmp/want.log"
cmp -s "$tmp/printed.log" "$tmp/want.log" && ok "printed output" || bad "printed output"

# Filters: J1939 PGN (any priority and source), id and mask, start and end.
n_ccvs1=$(grep -c ' 18FEF1..#' "$drive")
"$rp" --dry-run -t --pgn 65265 -I "$drive" >"$tmp/pgn.log" 2>/dev/null
[ "$(wc -l <"$tmp/pgn.log")" -eq "$n_ccvs1" ] && [ "$n_ccvs1" -gt 0 ] &&
    ! grep -v ' 18FEF1..#' "$tmp/pgn.log" >/dev/null && ok "--pgn 65265: $n_ccvs1 frames" ||
    bad "--pgn 65265"
"$rp" --dry-run -t --pgn 0xFEF1 --filter 0CF01300:1FFFFFFF -I "$drive" >"$tmp/both.log" 2>/dev/null
n_ssi00=$(grep -c ' 0CF01300#' "$drive")
[ "$(wc -l <"$tmp/both.log")" -eq $((n_ccvs1 + n_ssi00)) ] &&
    ok "--pgn or --filter: $((n_ccvs1 + n_ssi00)) frames" || bad "--pgn or --filter"
n_ssi=$(grep -c ' 0CF013..#' "$drive")
"$rp" --dry-run -t --filter 0CF01300:1FFFFF00 -I "$drive" >"$tmp/ssi.log" 2>/dev/null
[ "$(wc -l <"$tmp/ssi.log")" -eq "$n_ssi" ] && [ "$n_ssi" -gt 0 ] &&
    ! grep -v ' 0CF013..#' "$tmp/ssi.log" >/dev/null && ok "--filter ID:MASK: $n_ssi frames" ||
    bad "--filter ID:MASK"
# frames from 10 s to 20 s after the first (both ends included), by awk
t0=$(head -n 1 "$drive" | cut -d' ' -f1 | tr -d '()')
want=$(awk -v t0="$t0" '{ t = substr($1, 2, length($1) - 2) - t0; if (t >= 10 - 1e-7 && t <= 20 + 1e-7) n++ } END { print n }' "$drive")
"$rp" --dry-run -t --start 10 --end 20 -I "$drive" >"$tmp/slice.log" 2>/dev/null
[ "$(wc -l <"$tmp/slice.log")" -eq "$want" ] && ok "--start 10 --end 20: $want frames" ||
    bad "--start --end: $(wc -l <"$tmp/slice.log") frames, $want expected"

# Loops: three passes; standard input cannot loop.
"$rp" --dry-run -t -l 3 -I "$drive" >"$tmp/loop.log" 2>/dev/null
[ "$(wc -l <"$tmp/loop.log")" -eq $((3 * n_drive)) ] && ok "-l 3" || bad "-l 3"
expect_exit "-l with standard input" 3 "-l needs a file" "$rp" --dry-run -l 2

# Pacing: 2 s of the drive at 4x speed takes 0.5 s, not less.
t_start=$(date +%s%N)
"$rp" --dry-run --speed 4 --end 2 -I "$drive" >"$tmp/paced.log" 2>"$tmp/err"
t_end=$(date +%s%N)
ms=$(((t_end - t_start) / 1000000))
if [ "$ms" -ge 500 ] && [ "$ms" -lt 5000 ] && grep -q "lateness p50" "$tmp/err"; then
    ok "--speed 4 --end 2 took $ms ms; $(grep lateness "$tmp/err" | cut -d' ' -f2-)"
else
    bad "pacing: $ms ms"
fi
# -s: a pause of 100 s in the log is cut out
printf '%s\n' '(1700000000.000000) vcan0 123#01' '(1700000100.000000) vcan0 123#02' \
    '(1700000100.100000) vcan0 123#03' >"$tmp/gap.log"
t_start=$(date +%s%N)
"$rp" --dry-run -s 1 -I "$tmp/gap.log" >"$tmp/gap_out.log" 2>/dev/null
t_end=$(date +%s%N)
ms=$(((t_end - t_start) / 1000000))
[ "$ms" -ge 100 ] && [ "$ms" -lt 3000 ] && [ "$(wc -l <"$tmp/gap_out.log")" -eq 3 ] &&
    ok "-s 1 cuts a 100 s pause ($ms ms)" || bad "-s 1: $ms ms"
# -s with --start: a pause before the start point does not shift the rest,
# which keeps its 1 s spacing
printf '%s\n' '(1700000000.000000) vcan0 123#01' '(1700000100.000000) vcan0 123#02' \
    '(1700000101.000000) vcan0 123#03' '(1700000102.000000) vcan0 123#04' >"$tmp/gap2.log"
t_start=$(date +%s%N)
"$rp" --dry-run -s 5 --start 50 -I "$tmp/gap2.log" >"$tmp/gap2_out.log" 2>/dev/null
t_end=$(date +%s%N)
ms=$(((t_end - t_start) / 1000000))
[ "$ms" -ge 1950 ] && [ "$ms" -lt 4000 ] && [ "$(wc -l <"$tmp/gap2_out.log")" -eq 3 ] &&
    ok "-s 5 --start 50: the pause cut, 1 s steps kept ($ms ms)" || bad "-s 5 --start 50: $ms ms"
# SIGTERM: the summary, exit 130
"$rp" --dry-run -I "$drive" >/dev/null 2>"$tmp/term.txt" &
pid=$!
sleep 0.5
kill -TERM "$pid"
wait "$pid"
rc=$?
[ "$rc" -eq 130 ] && grep -q "written to stdout" "$tmp/term.txt" && ok "SIGTERM: summary, exit 130" ||
    bad "SIGTERM: exit $rc"
# -n: a count of frames
"$rp" --dry-run -t -n 5 -I "$drive" >"$tmp/n.log" 2>/dev/null
[ "$(wc -l <"$tmp/n.log")" -eq 5 ] && ok "-n 5" || bad "-n 5"

# Bad input: file, line and reason, exit 1; --skip-errors skips and counts.
printf '%s\n' '(1700000000.000000) vcan0 123#01' '(1700000000.010000) vcan0 123#0G' \
    '(1700000000.020000) vcan0 123#03' >"$tmp/bad.log"
expect_exit "bad hex stops" 1 "$tmp/bad.log:2: bad hex: 'G' in the data" \
    "$rp" --dry-run -t -I "$tmp/bad.log"
expect_exit "--skip-errors" 0 "1 x bad hex, the first: $tmp/bad.log:2: bad hex" \
    "$rp" --dry-run -t --skip-errors -I "$tmp/bad.log"
[ "$(wc -l <"$tmp/out")" -eq 2 ] && ok "--skip-errors: 2 frames" || bad "--skip-errors frames"
printf '%s\n' '(1700000000.000000) vcan0 123#01' '(1700000000.010000) vcan0 123#001122334455667788' >"$tmp/dlc.log"
expect_exit "9 data bytes" 1 "$tmp/dlc.log:2: bad length: 9 data bytes, over 8 for classic CAN" \
    "$rp" --dry-run -t -I "$tmp/dlc.log"
printf '%s\n' '(1700000000.010000) vcan0 123#01' '(1700000000.000000) vcan0 123#02' >"$tmp/back.log"
expect_exit "timestamps backwards" 1 "$tmp/back.log:2: timestamp going backwards" \
    "$rp" --dry-run -t -I "$tmp/back.log"
printf '(1700000000.0000' >"$tmp/trunc.log"
expect_exit "truncated last line" 1 "$tmp/trunc.log:1: truncated line: line ends in the timestamp" \
    "$rp" --dry-run -t -I "$tmp/trunc.log"
: >"$tmp/empty.log"
expect_exit "empty file" 1 "$tmp/empty.log: empty file: no CAN frames (0 lines)" \
    "$rp" --dry-run -t -I "$tmp/empty.log"
head -c 4000 "$rp" >"$tmp/binary.log"
expect_exit "binary file" 1 "$tmp/binary.log:1: binary content" "$rp" --dry-run -t -I "$tmp/binary.log"
expect_exit "binary file, skipping" 1 "no frame could be read" \
    "$rp" --dry-run -t --skip-errors -I "$tmp/binary.log"
expect_exit "missing file" 1 "cannot open $tmp/none.log" "$rp" --dry-run -I "$tmp/none.log"
expect_exit "unknown option" 3 "unknown option --frobnicate" "$rp" --frobnicate
expect_exit "bad assignment" 3 "an assignment is TX=LOG" "$rp" -I "$drive" vcan0
expect_exit "bad --speed" 3 "--speed 0: a factor" "$rp" --speed 0 -I "$drive"

# The real-bus guard: lo is not virtual CAN; refused before anything is sent.
expect_exit "guard: lo=vcan0 refused" 2 \
    "refusing to send on lo: it is not a CAN interface. Only virtual CAN (vcan, vxcan) is allowed unless --allow-real-bus is given." \
    "$rp" -I "$drive" lo=vcan0
[ ! -s "$tmp/out" ] && ok "guard: nothing written" || bad "guard: output"
printf '%s\n' '(1700000000.000000) lo 123#01' >"$tmp/lo.log"
expect_exit "guard: a log of lo refused" 2 "refusing to send on lo" "$rp" -I "$tmp/lo.log"
expect_exit "guard: lo with --allow-real-bus is still not CAN" 1 "lo is not a CAN interface" \
    "$rp" --allow-real-bus -I "$tmp/lo.log"
expect_exit "no such interface" 1 "cannot send on nosuch0: no such interface" \
    "$rp" -I "$drive" nosuch0=vcan0
expect_exit "--skip-unknown" 0 "no interface nosuch0: its frames are skipped" \
    "$rp" --skip-unknown -t -I "$drive" nosuch0=vcan0

if [ -n "$ecu_replay" ]; then
    # The drive as a bench records it: candump -t z (times from the first
    # frame) and -t A (dates), two blanks apart, bytes spaced.
    awk '{ t = substr($1, 2, length($1) - 2); split($3, a, "#"); d = a[2]; s = "";
           for (i = 1; i <= length(d); i += 2) s = s " " substr(d, i, 2);
           printf "(%s)  %s  %8s   [%d] %s\n", t, $2, a[1], length(d) / 2, s }' "$drive" \
        >"$tmp/drive_ta.txt"
    awk '{ t = substr($1, 2, length($1) - 2) - 1700000000;
           sub(/^\([0-9]+\.[0-9]+\)/, sprintf("(%03d.%06d)", int(t), (t - int(t)) * 1000000 + 0.5)); print }' \
        "$tmp/drive_ta.txt" >"$tmp/drive_tz.txt"
    "$ecu_replay" --log "$drive" --record "$tmp/rec_log.log" >"$tmp/sum_log.txt" 2>"$tmp/err"
    "$ecu_replay" --log "$tmp/drive_ta.txt" --record "$tmp/rec_ta.log" >"$tmp/sum_ta.txt" 2>>"$tmp/err"
    if cmp -s "$tmp/rec_log.log" "$tmp/rec_ta.log" && cmp -s "$tmp/sum_log.txt" "$tmp/sum_ta.txt"; then
        ok "pfe_ecu_replay: printed -t a, the same record ($(wc -l <"$tmp/rec_ta.log") lines)"
    else
        bad "pfe_ecu_replay: printed -t a record differs"; cat "$tmp/err"
    fi
    "$ecu_replay" --log "$tmp/drive_tz.txt" --record "$tmp/rec_tz.log" >"$tmp/sum_tz.txt" 2>"$tmp/err"
    # -t z counts from the first frame: the same record 1700000000 s earlier
    awk '{ t = substr($1, 2, length($1) - 2) - 1700000000;
           sub(/^\([0-9]+\.[0-9]+\)/, sprintf("(%d.%06d)", int(t), (t - int(t)) * 1000000 + 0.5)); print }' \
        "$tmp/rec_log.log" >"$tmp/rec_log_z.log"
    if cmp -s "$tmp/rec_log_z.log" "$tmp/rec_tz.log" && grep -q ' frames 6997 .* bad 0 ' "$tmp/sum_tz.txt"; then
        ok "pfe_ecu_replay: printed -t z, the same record from 0 s"
    else
        bad "pfe_ecu_replay: printed -t z"; cat "$tmp/err" "$tmp/sum_tz.txt"; cmp "$tmp/rec_log_z.log" "$tmp/rec_tz.log"
    fi
    # -t d: the time since the frame before, read with --format printed-delta
    awk '{ t = substr($1, 2, length($1) - 2) - 1700000000; us = int(t * 1000000 + 0.5);
           d = (NR == 1) ? 0 : us - prev; prev = us;
           sub(/^\([0-9]+\.[0-9]+\)/, sprintf("(%03d.%06d)", int(d / 1000000), d % 1000000)); print }' \
        "$tmp/drive_ta.txt" >"$tmp/drive_td.txt"
    "$ecu_replay" --log "$tmp/drive_td.txt" --format printed-delta --record "$tmp/rec_td.log" \
        >/dev/null 2>"$tmp/err"
    if cmp -s "$tmp/rec_tz.log" "$tmp/rec_td.log"; then
        ok "pfe_ecu_replay: printed -t d with --format printed-delta, the -t z record"
    else
        bad "pfe_ecu_replay: printed -t d"; cat "$tmp/err"; head -n 3 "$tmp/drive_td.txt"
    fi
    # -t A: 1700000000 s is 2023-11-14 22:13:20 UTC; the drive lasts a minute
    awk '{ t = substr($1, 2, length($1) - 2) - 1700000000; s = int(t); us = int((t - s) * 1000000 + 0.5);
           m = 13 + int((20 + s) / 60); sec = (20 + s) % 60;
           sub(/^\([0-9]+\.[0-9]+\)/, sprintf("(2023-11-14 22:%02d:%02d.%06d)", m, sec, us)); print }' \
        "$tmp/drive_ta.txt" >"$tmp/drive_tA.txt"
    "$ecu_replay" --log "$tmp/drive_tA.txt" --record "$tmp/rec_tA.log" >"$tmp/sum_tA.txt" 2>"$tmp/err"
    if cmp -s "$tmp/rec_log.log" "$tmp/rec_tA.log" && cmp -s "$tmp/sum_log.txt" "$tmp/sum_tA.txt"; then
        ok "pfe_ecu_replay: printed -t A (dates read as UTC), the same record"
    else
        bad "pfe_ecu_replay: printed -t A"; cat "$tmp/err"; head -n 2 "$tmp/drive_tA.txt"
    fi
    if command -v log2asc >/dev/null 2>&1; then
        log2asc -I "$drive" vcan0 >"$tmp/drive_ecu.asc" 2>/dev/null
        "$ecu_replay" --log "$tmp/drive_ecu.asc" --record "$tmp/rec_asc.log" >/dev/null 2>"$tmp/err"
        # ASC counts from the start and names channel 1 can0
        sed 's/ can0 / vcan0 /' "$tmp/rec_asc.log" | cut -d' ' -f2- >"$tmp/rec_asc_f"
        cut -d' ' -f2- "$tmp/rec_log.log" >"$tmp/rec_log_f"
        cmp -s "$tmp/rec_log_f" "$tmp/rec_asc_f" && ok "pfe_ecu_replay: ASC, the same frames" ||
            { bad "pfe_ecu_replay: ASC"; cat "$tmp/err"; }
    fi
    mkdir -p "$tmp/adir"
    expect_exit "pfe_ecu_replay: a directory" 2 "cannot read $tmp/adir: is a directory, not a CAN log" \
        "$ecu_replay" --log "$tmp/adir"
    { head -n 3 "$drive"; echo '(1700000000.020000) vcan0 18FEF100#GG'; tail -n +4 "$drive" | head -n 20; } \
        >"$tmp/badline.log"
    expect_exit "pfe_ecu_replay: a bad line named with its file, line and reason" 1 \
        "1 bad lines skipped; the first: $tmp/badline.log:4: bad hex: 'G' in the data" \
        "$ecu_replay" --log "$tmp/badline.log"
    sed 's/^([^)]*)  //' "$tmp/drive_ta.txt" | head -n 50 >"$tmp/notime.txt"
    expect_exit "pfe_ecu_replay: printed output without -t" 2 \
        "no classic CAN frame in the log (50 lines, 50 bad, 0 not classic CAN); the first bad line: $tmp/notime.txt:1: no timestamp" \
        "$ecu_replay" --log "$tmp/notime.txt"
    expect_exit "pfe_ecu_replay: bad --format" 2 "--format wants auto, log" \
        "$ecu_replay" --log "$drive" --format csv
fi
if [ -n "$ecu" ]; then
    expect_exit "pfe_ecu: an empty interface name" 2 "--iface needs an interface name" \
        "$ecu" --iface '' --nvm "$tmp/f.nvm"
    expect_exit "pfe_ecu: no such interface" 1 "no such interface nosuch0" \
        "$ecu" --iface nosuch0 --nvm "$tmp/f.nvm"
    expect_exit "pfe_ecu: lo is not CAN" 1 "lo is not a CAN interface" \
        "$ecu" --iface lo --nvm "$tmp/f.nvm"
    expect_exit "pfe_ecu: lo is not CAN, --allow-real-bus or not" 1 "lo is not a CAN interface" \
        "$ecu" --iface lo --nvm "$tmp/f.nvm" --allow-real-bus
    expect_exit "pfe_ecu: a name too long" 2 "cannot be an interface name" \
        "$ecu" --iface 0123456789abcdefgh --nvm "$tmp/f.nvm"
    [ ! -e "$tmp/f.nvm" ] && ok "pfe_ecu: no NVM file written when refused" || bad "pfe_ecu: NVM file"
fi

echo "test_replay: $failed failure(s)"
[ "$failed" -eq 0 ]

#!/bin/sh
# The codec generated from the DBC: a change in the DBC alone changes the
# firmware, and the unchanged DBC gives the build's tables.
#
#   CC=gcc CFLAGS='...' tests/codec_gen/codec_gen_test.sh DBC2C DBC GEN_C GEN_H WORK_DIR
#
# DBC2C the generator, DBC can_dbc/pfe.dbc, GEN_C and GEN_H the tables and
# the header the build wrote from it (build/gen/pfe_dbc.c, pfe_dbc.h). In
# WORK_DIR (a scratch folder, emptied):
#   1. dbc2c on the unchanged DBC writes GEN_C and GEN_H byte for byte, and
#      the firmware built over them behaves as the DBC says
#      (tests/codec_gen/codec_gen_probe.c);
#   2. on a copy with six changes, the firmware built over the regenerated
#      tables and header, and nothing else, follows each one:
#        LFE1 EngineFuelRate scale 0.05 -> 0.1 L/h: 36 L/h is sent as raw 360
#          (0x0168) instead of 720 (0x02D0);
#        PFE_Status GenMsgCycleTime 1000 -> 500 ms: 20 frames in 10 s, not 10;
#        CCVS1 WheelBasedVehicleSpeed in m/s at 0.01 instead of km/h at 1/256:
#          raw 0x1000 reads 40.96 m/s = 40960 mm/s instead of 16 km/h = 4444 mm/s;
#        PFE_GradePreview GradeSample1 scale 0.002 -> 0.004 %, offset -64 -> -128:
#          three samples of raw 33000 read 2 %, 4 %, 2 % (20000, 40000, 20000 ppm)
#          instead of 2 % each;
#        CVW PFEInputPeriod 1000 -> 2000 ms: a second sender's mass, 4 s after
#          the first sender's last, is taken (silent 3 periods of 1 s) before
#          and ignored after (not 3 periods of 2 s);
#        PFE_Status's PGN 65284 -> 65290 (0xFF0A): PFE_PGN_STATUS follows, and
#          the 20 status frames the ECU sends in 10 s carry it (none 65284);
#   3. dbc2c refuses, with exit status 1 and a message naming the cause, a
#      missing file, a DBC without a signal the firmware needs, a min that is
#      not a whole raw count, a unit the firmware cannot convert and an
#      input the firmware watches without a period; and exits 2 on a usage
#      error (no arguments, or no header argument).
# Prints every figure it compares; exits 1 when one differs.

set -u

if [ $# -ne 5 ]; then
    echo "usage: $0 DBC2C DBC GEN_C GEN_H WORK_DIR" >&2
    exit 2
fi
DBC2C=$1
DBC=$2
GEN_C=$3
GEN_H=$4
W=$5
CC=${CC:-gcc}
CFLAGS=${CFLAGS:--std=c11 -Wall -Wextra -Werror -I. -Ifirmware -O1}

rm -rf "${W:?}"
mkdir -p "$W"
bad=0

say_bad() {
    echo "FAIL: $*"
    bad=1
}

# gen NAME DBC: dbc2c writes $W/NAME/pfe_dbc.c and pfe_dbc.h from DBC
gen() {
    mkdir -p "$W/$1" && "$DBC2C" "$2" "$W/$1/pfe_dbc.c" "$W/$1/pfe_dbc.h"
}

# probe NAME: the firmware over $W/NAME/pfe_dbc.c and its header (first on
# the include path, before the build's), its figures in $W/NAME.out
probe() {
    # shellcheck disable=SC2086
    if ! $CC -I"$W/$1" $CFLAGS -o "$W/$1/probe" tests/codec_gen/codec_gen_probe.c firmware/*.c \
        "$W/$1/pfe_dbc.c"; then
        say_bad "$1: the firmware does not build over $W/$1"
        return 1
    fi
    if ! "$W/$1/probe" >"$W/$1.out"; then
        say_bad "$1: the probe failed"
        return 1
    fi
    return 0
}

# expect NAME KEY VALUE: the probe's line KEY is VALUE
expect() {
    got=$(sed -n "s/^$2 //p" "$W/$1.out")
    if [ "$got" = "$3" ]; then
        echo "ok: $1 $2 = $got"
    else
        say_bad "$1 $2: expected '$3', got '$got'"
    fi
}

# refuse NAME STATUS PATTERN ARGS...: dbc2c exits STATUS, stderr matches PATTERN
refuse() {
    rname=$1
    want=$2
    pattern=$3
    shift 3
    "$DBC2C" "$@" >"$W/refuse.out" 2>"$W/refuse.err"
    rc=$?
    if [ "$rc" -ne "$want" ]; then
        say_bad "$rname: exit status $rc, expected $want ($(cat "$W/refuse.err"))"
    elif ! grep -q -e "$pattern" "$W/refuse.err"; then
        say_bad "$rname: no '$pattern' in: $(cat "$W/refuse.err")"
    else
        echo "ok: $rname refused ($rc): $(head -n 1 "$W/refuse.err")"
    fi
}

echo "== the unchanged DBC"
if gen same "$DBC" && cmp "$W/same/pfe_dbc.c" "$GEN_C" && cmp "$W/same/pfe_dbc.h" "$GEN_H"; then
    echo "ok: dbc2c $DBC writes $GEN_C and $GEN_H byte for byte"
else
    say_bad "dbc2c on $DBC does not write $GEN_C and $GEN_H"
fi
if probe same; then
    expect same lfe1_data "D0 02 FF FF FF FF FF FF"
    expect same speed_mm_s 4444
    expect same speed_unit km/h
    expect same status_frames 10
    expect same status_cycle_ms 1000
    expect same preview_ppm "20000 20000 20000"
    expect same preview_copy_ppm "20000 20000 20000"
    expect same cvw_second_sender_after_4s "taken"
    expect same status_pgn 65284
    expect same status_pgn_frames "65284:10 65290:0"
fi

echo "== a changed copy: LFE1 scale, PFE_Status period and PGN, CCVS1 speed unit, GradeSample1 scale, CVW period"
# PFE_Status: id 0x98FF048C -> 0x98FF0A8C (2566849676 -> 2566851212), every line naming it
sed -e '/^ SG_ EngineFuelRate /s/(0.05,0) \[0|3212.75\]/(0.1,0) [0|6425.5]/' \
    -e 's/^BA_ "GenMsgCycleTime" BO_ 2566849676 1000;/BA_ "GenMsgCycleTime" BO_ 2566849676 500;/' \
    -e '/^ SG_ WheelBasedVehicleSpeed /s/(0.00390625,0) \[0|250.99609375\] "km\/h"/(0.01,0) [0|642.55] "m\/s"/' \
    -e '/^ SG_ GradeSample1 /s/(0.002,-64) \[-64|64.51\]/(0.004,-128) [-128|129.02]/' \
    -e 's/^BA_ "PFEInputPeriod" BO_ 2566811648 1000;/BA_ "PFEInputPeriod" BO_ 2566811648 2000;/' \
    -e 's/2566849676/2566851212/g' \
    "$DBC" >"$W/changed.dbc"
changes=$(diff "$DBC" "$W/changed.dbc" | grep -c '^>')
id_lines=$(grep -c 2566849676 "$DBC")
# four lines of their own, and the id's lines (PFE_Status's period among them)
if [ "$changes" -ne $((4 + id_lines)) ]; then
    say_bad "the copy differs from $DBC in $changes lines, not $((4 + id_lines)) (4 and PFE_Status's id on $id_lines lines)"
fi
if gen changed "$W/changed.dbc" && probe changed; then
    expect changed lfe1_data "68 01 FF FF FF FF FF FF"
    expect changed speed_mm_s 40960
    expect changed speed_unit m/s
    expect changed status_frames 20
    expect changed status_cycle_ms 500
    expect changed preview_ppm "20000 40000 20000"
    expect changed preview_copy_ppm "20000 40000 20000"
    expect changed cvw_second_sender_after_4s "ignored"
    expect changed status_pgn 65290
    expect changed status_pgn_frames "65284:0 65290:20"
else
    say_bad "no firmware from the changed copy"
fi

echo "== what dbc2c refuses"
refuse "missing file" 1 "$W/no-such.dbc" "$W/no-such.dbc" "$W/out.c" "$W/out.h"
sed -e 's/EngineFuelRate/EngineFuelRat/g' "$DBC" >"$W/no-signal.dbc"
refuse "a signal the firmware needs missing" 1 "no signal EngineFuelRate" "$W/no-signal.dbc" "$W/out.c" "$W/out.h"
sed -e '/^ SG_ EngineFuelRate /s/\[0|3212.75\]/[0.01|3212.75]/' "$DBC" >"$W/bad-min.dbc"
refuse "a min between raw counts" 1 "min 0.01 is not a whole number" "$W/bad-min.dbc" "$W/out.c" "$W/out.h"
sed -e '/^ SG_ EngineFuelRate /s/"L\/h"/"gal\/h"/' "$DBC" >"$W/bad-unit.dbc"
refuse "a unit the firmware cannot convert" 1 'unit "gal/h"' "$W/bad-unit.dbc" "$W/out.c" "$W/out.h"
sed -e '/^BA_ "PFEInputPeriod" BO_ 2566811648 1000;/d' "$DBC" >"$W/no-period.dbc"
refuse "an input without a period" 1 "CVW: an input the firmware watches needs" "$W/no-period.dbc" "$W/out.c" "$W/out.h"
refuse "no arguments" 2 "usage: dbc2c"
refuse "no header argument" 2 "usage: dbc2c" "$DBC" "$W/out.c"
if [ -e "$W/out.c" ] || [ -e "$W/out.h" ]; then
    say_bad "a refused run left $W/out.c or $W/out.h"
fi

if [ "$bad" -ne 0 ]; then
    echo "codec_gen_test: FAILED"
    exit 1
fi
echo "codec_gen_test: passed"

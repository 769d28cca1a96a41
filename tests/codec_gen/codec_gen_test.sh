#!/bin/sh
# The codec generated from the DBC: a change in the DBC alone changes the
# firmware, and the unchanged DBC gives the build's tables.
#
#   CC=gcc CFLAGS='...' tests/codec_gen/codec_gen_test.sh DBC2C DBC GEN_C WORK_DIR
#
# DBC2C the generator, DBC can_dbc/pfe.dbc, GEN_C the tables the build wrote
# from it (build/gen/pfe_dbc.c). In WORK_DIR (a scratch folder, emptied):
#   1. dbc2c on the unchanged DBC writes GEN_C byte for byte, and the firmware
#      built over it behaves as the DBC says (tests/codec_gen/codec_gen_probe.c);
#   2. on a copy with three changes, the firmware built over the regenerated
#      tables, and nothing else, follows each one:
#        LFE1 EngineFuelRate scale 0.05 -> 0.1 L/h: 36 L/h is sent as raw 360
#          (0x0168) instead of 720 (0x02D0);
#        PFE_Status GenMsgCycleTime 1000 -> 500 ms: 20 frames in 10 s, not 10;
#        CCVS1 WheelBasedVehicleSpeed in m/s at 0.01 instead of km/h at 1/256:
#          raw 0x1000 reads 40.96 m/s = 40960 mm/s instead of 16 km/h = 4444 mm/s;
#   3. dbc2c refuses, with exit status 1 and a message naming the cause, a
#      missing file, a DBC without a signal the firmware needs, a min that is
#      not a whole raw count and a unit the firmware cannot convert; and
#      exits 2 on a usage error.
# Prints every figure it compares; exits 1 when one differs.

set -u

if [ $# -ne 4 ]; then
    echo "usage: $0 DBC2C DBC GEN_C WORK_DIR" >&2
    exit 2
fi
DBC2C=$1
DBC=$2
GEN_C=$3
W=$4
CC=${CC:-gcc}
CFLAGS=${CFLAGS:--std=c11 -Wall -Wextra -Werror -I. -Ifirmware -O1}

rm -rf "${W:?}"
mkdir -p "$W"
bad=0

say_bad() {
    echo "FAIL: $*"
    bad=1
}

# probe NAME GEN.c: the firmware over GEN.c, its figures in $W/NAME.out
probe() {
    # shellcheck disable=SC2086
    if ! $CC $CFLAGS -o "$W/$1" tests/codec_gen/codec_gen_probe.c firmware/*.c "$2"; then
        say_bad "$1: the firmware does not build over $2"
        return 1
    fi
    if ! "$W/$1" >"$W/$1.out"; then
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
if "$DBC2C" "$DBC" "$W/same.c" && cmp "$W/same.c" "$GEN_C"; then
    echo "ok: dbc2c $DBC writes $GEN_C byte for byte"
else
    say_bad "dbc2c on $DBC does not write $GEN_C"
fi
if probe same "$W/same.c"; then
    expect same lfe1_data "D0 02 FF FF FF FF FF FF"
    expect same speed_mm_s 4444
    expect same speed_unit km/h
    expect same status_frames 10
    expect same status_cycle_ms 1000
fi

echo "== a changed copy: LFE1 scale, PFE_Status period, CCVS1 speed unit"
sed -e '/^ SG_ EngineFuelRate /s/(0.05,0) \[0|3212.75\]/(0.1,0) [0|6425.5]/' \
    -e 's/^BA_ "GenMsgCycleTime" BO_ 2566849676 1000;/BA_ "GenMsgCycleTime" BO_ 2566849676 500;/' \
    -e '/^ SG_ WheelBasedVehicleSpeed /s/(0.00390625,0) \[0|250.99609375\] "km\/h"/(0.01,0) [0|642.55] "m\/s"/' \
    "$DBC" >"$W/changed.dbc"
changes=$(diff "$DBC" "$W/changed.dbc" | grep -c '^>')
if [ "$changes" -ne 3 ]; then
    say_bad "the copy differs from $DBC in $changes lines, not 3"
fi
if "$DBC2C" "$W/changed.dbc" "$W/changed.c" && probe changed "$W/changed.c"; then
    expect changed lfe1_data "68 01 FF FF FF FF FF FF"
    expect changed speed_mm_s 40960
    expect changed speed_unit m/s
    expect changed status_frames 20
    expect changed status_cycle_ms 500
else
    say_bad "no firmware from the changed copy"
fi

echo "== what dbc2c refuses"
refuse "missing file" 1 "$W/no-such.dbc" "$W/no-such.dbc" "$W/out.c"
sed -e 's/EngineFuelRate/EngineFuelRat/g' "$DBC" >"$W/no-signal.dbc"
refuse "a signal the firmware needs missing" 1 "no signal EngineFuelRate" "$W/no-signal.dbc" "$W/out.c"
sed -e '/^ SG_ EngineFuelRate /s/\[0|3212.75\]/[0.01|3212.75]/' "$DBC" >"$W/bad-min.dbc"
refuse "a min between raw counts" 1 "min 0.01 is not a whole number" "$W/bad-min.dbc" "$W/out.c"
sed -e '/^ SG_ EngineFuelRate /s/"L\/h"/"gal\/h"/' "$DBC" >"$W/bad-unit.dbc"
refuse "a unit the firmware cannot convert" 1 'unit "gal/h"' "$W/bad-unit.dbc" "$W/out.c"
refuse "no arguments" 2 "usage: dbc2c"
if [ -e "$W/out.c" ]; then
    say_bad "a refused run left $W/out.c"
fi

if [ "$bad" -ne 0 ]; then
    echo "codec_gen_test: FAILED"
    exit 1
fi
echo "codec_gen_test: passed"

#!/bin/sh
# pfe_decode on literal frames: every value hand-computed from can_dbc/pfe.dbc,
# not-available and error values shown as NA and ERR, never as numbers.
#
#   tests/host/test_decode.sh PFE_DECODE DBC
#
# Exit status: 0 when every check passes, 1 otherwise (each failure printed).
set -u
dec=$1
dbc=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0

# $1 name, $2 expected file, $3 got file
same() {
    if cmp -s "$2" "$3"; then
        echo "test_decode: $1 ok"
    else
        echo "test_decode: $1 FAILED; difference (expected, got):"
        diff "$2" "$3"
        failed=$((failed + 1))
    fi
}

# CCVS1: 90 km/h = 23040 = 0x5A00; 89.99609375 = 23039; 0xFFxx not
#   available, 0xFExx error; priority 3 and source 0x17 change nothing;
#   2 bytes are too short for bytes 2-3
# SSI: pitch 0x7D00 = 32000 -> 32000 * 0.002 - 64 = 0; 0x7A12 = 31250 ->
#   -1.5 deg; roll 0xFFFF not available; figure of merit 10b error
# PFE_GradePreview: header (mux 0): byte 0 = id 5 << 2; 1000 samples, 12 m;
#   data (mux 1): byte 0 = 1 | 5 << 2 | (3 & 3) << 6 = 0xD5, index 3;
#   2 % = (2 + 64) / 0.002 = 33000 = 0x80E8; 0xFFFF; 0xFE00
# PFE_Status: byte 0 = 0 | 3 << 2 | 1 << 4 | 2 << 6 = 0x9C (plain states:
#   numbers with their VAL_ text); 0xFF, 0xFE, 0xFB in 8-bit counters with
#   J1939 ranges: NA, ERR, out of range; byte 5 = 1 | 0 << 2 | 3 << 4 | 2 << 6
# PFE_PlatoonFuel: 30.5 L/h = 610 = 0x0262; 1234.567 L = 1234567 = 0x0012D687
# PFE_PlatoonConfig: 33 vehicles is over [1|32]; 1.5 s = 1500 = 0x05DC;
#   80 km/h = 20480 = 0x5000
# Request (PDU1, to 0x8C and to all): PGN 65266 = 0x00FEF2
cat >"$tmp/in.log" <<'LOG'
(1700000000.000000) vcan0 18FEF100#FF005AFFFFFFFFFF
(1700000000.010000) vcan0 18FEF100#FFFF59FFFFFFFFFF
(1700000000.020000) vcan0 18FEF100#FFFFFFFFFFFFFFFF
(1700000000.030000) vcan0 18FEF100#FF00FEFFFFFFFFFF
(1700000000.040000) vcan0 0CFEF117#FF005AFFFFFFFFFF
(1700000000.050000) vcan0 18FEF100#FF00
(1700000000.060000) vcan0 0CF01300#007DFFFFFFFFFEFF
(1700000000.070000) vcan0 0CF01300#127A007DFFFFFCFF
(1700000000.080000) vcan0 18FF0100#14E8030CFFFFFFFF
(1700000000.090000) vcan0 18FF0100#D500E880FFFF00FE
(1700000000.100000) vcan0 18FF048C#9CFFFEFB07B1FFFF
(1700000000.110000) vcan0 18FF028C#620287D61200FFFF
(1700000000.120000) vcan0 18FF0000#2100FFFFDC050050
(1700000000.130000) vcan0 18EA8C00#F2FE00
(1700000000.140000) vcan0 18EAFF00#F2FE00
(1700000000.150000) vcan0 18FEF100#R
(1700000000.160000) vcan0 18FECA00#0102
(1700000000.170000) vcan0 123#AA
(1700000000.180000) vcan0 20000080#0000000000000000
LOG
cat >"$tmp/want.txt" <<'OUT'
1700000000.000000 vcan0 18FEF100 CCVS1 WheelBasedVehicleSpeed=90 km/h
1700000000.010000 vcan0 18FEF100 CCVS1 WheelBasedVehicleSpeed=89.99609375 km/h
1700000000.020000 vcan0 18FEF100 CCVS1 WheelBasedVehicleSpeed=NA
1700000000.030000 vcan0 18FEF100 CCVS1 WheelBasedVehicleSpeed=ERR
1700000000.040000 vcan0 0CFEF117 CCVS1 WheelBasedVehicleSpeed=90 km/h
1700000000.050000 vcan0 18FEF100 CCVS1 WheelBasedVehicleSpeed=SHORT
1700000000.060000 vcan0 0CF01300 SSI PitchAngle=0 deg RollAngle=NA PitchAngleFigureOfMerit=ERR
1700000000.070000 vcan0 0CF01300 SSI PitchAngle=-1.5 deg RollAngle=0 deg PitchAngleFigureOfMerit=0 (FullyFunctional)
1700000000.080000 vcan0 18FF0100 PFE_GradePreview PreviewFrameType=0 (Header) PreviewId=5 SampleCount=1000 SampleSpacing=12 m
1700000000.090000 vcan0 18FF0100 PFE_GradePreview PreviewFrameType=1 (Data) PreviewId=5 SampleIndex=3 GradeSample0=2 % GradeSample1=NA GradeSample2=ERR
1700000000.100000 vcan0 18FF048C PFE_Status SpeedInputState=0 (Valid) GradeInputState=3 (NotAvailableOrTimedOut) PlatoonConfigInputState=1 (OutOfRange) GradePreviewInputState=2 (Error) DegradedMode=NA RxFramesDropped=ERR TickOverruns=OOR(raw 251) TxFramesDropped=7 frames WarmingUp=1 (On) SpeedClamped=0 (Off) GradeClamped=NA OutputSaturated=ERR InputsRejected=NA AddressConflicts=NA
1700000000.110000 vcan0 18FF028C PFE_PlatoonFuel PlatoonFuelRate=30.5 L/h PlatoonTotalFuelUsed=1234.567 L
1700000000.120000 vcan0 18FF0000 PFE_PlatoonConfig NumberOfVehicles=OOR(raw 33) OwnPosition=0 Gap=NA TimeGap=1.5 s SetSpeed=80 km/h
1700000000.130000 vcan0 18EA8C00 Request RequestedPGN=65266
1700000000.140000 vcan0 18EAFF00 Request RequestedPGN=65266
1700000000.150000 vcan0 18FEF100 CCVS1 remote request
1700000000.160000 vcan0 18FECA00 ? data=0102
1700000000.170000 vcan0 123 ? data=AA
1700000000.180000 vcan0 20000080 ERRORFRAME data=0000000000000000
OUT
"$dec" --dbc "$dbc" "$tmp/in.log" >"$tmp/got.txt" 2>"$tmp/err.txt"
rc=$?
same "text output" "$tmp/want.txt" "$tmp/got.txt"
grep -q "pfe_decode: 19 frames, 15 decoded, 3 not in the DBC, 0 parse errors" "$tmp/err.txt" ||
    { echo "test_decode: summary FAILED:"; cat "$tmp/err.txt"; failed=$((failed + 1)); }
[ "$rc" -eq 0 ] || { echo "test_decode: exit $rc, 0 expected"; failed=$((failed + 1)); }

# The same frames from standard input give the same lines.
"$dec" --dbc "$dbc" - <"$tmp/in.log" >"$tmp/got_stdin.txt" 2>/dev/null
same "standard input" "$tmp/want.txt" "$tmp/got_stdin.txt"

# CSV, two messages: their columns only, NA / ERR / SHORT in the cells.
cat >"$tmp/want.csv" <<'OUT'
time_s,iface,id,message,CCVS1.WheelBasedVehicleSpeed[km/h],SSI.PitchAngle[deg],SSI.RollAngle[deg],SSI.PitchAngleFigureOfMerit
1700000000.000000,vcan0,18FEF100,CCVS1,90,,,
1700000000.010000,vcan0,18FEF100,CCVS1,89.99609375,,,
1700000000.020000,vcan0,18FEF100,CCVS1,NA,,,
1700000000.030000,vcan0,18FEF100,CCVS1,ERR,,,
1700000000.040000,vcan0,0CFEF117,CCVS1,90,,,
1700000000.050000,vcan0,18FEF100,CCVS1,SHORT,,,
1700000000.060000,vcan0,0CF01300,SSI,,0,NA,ERR
1700000000.070000,vcan0,0CF01300,SSI,,-1.5,0,0
OUT
"$dec" --dbc "$dbc" --csv --message CCVS1 --message SSI "$tmp/in.log" >"$tmp/got.csv" 2>/dev/null
same "CSV of two messages" "$tmp/want.csv" "$tmp/got.csv"

# CSV of everything: a multiplexed message leaves the other branch empty.
"$dec" --dbc "$dbc" --csv "$tmp/in.log" >"$tmp/all.csv" 2>/dev/null
cols=$(head -n 1 "$tmp/all.csv" | tr ',' '\n' | wc -l)
# 4 columns (time, iface, id, message), then one per signal of the DBC
n_sig=$(grep -c '^ SG_ ' "$dbc")
[ "$cols" -eq $((4 + n_sig)) ] ||
    { echo "test_decode: CSV has $cols columns, 4 + $n_sig signals expected"; failed=$((failed + 1)); }
echo "test_decode: CSV of all messages: $cols columns"
header_row=$(grep ',PFE_GradePreview,' "$tmp/all.csv" | head -n 1 | cut -d, -f14-21)
[ "$header_row" = "0,5,1000,12,,,," ] ||
    { echo "test_decode: GradePreview header row: '$header_row'"; failed=$((failed + 1)); }
data_row=$(grep ',PFE_GradePreview,' "$tmp/all.csv" | tail -n 1 | cut -d, -f14-21)
[ "$data_row" = "1,5,,,3,2,NA,ERR" ] ||
    { echo "test_decode: GradePreview data row: '$data_row'"; failed=$((failed + 1)); }

# The same drive as Vector ASC decodes to the same values (time from 0).
cat >"$tmp/in.asc" <<'ASC'
date Tue Nov 14 22:13:20 2023
base hex  timestamps absolute
   0.000000 1  18FEF100x       Rx   d 8 FF 00 5A FF FF FF FF FF
   0.060000 1  CF01300x        Rx   d 8 00 7D FF FF FF FF FE FF
ASC
cat >"$tmp/want_asc.txt" <<'OUT'
0.000000 can0 18FEF100 CCVS1 WheelBasedVehicleSpeed=90 km/h
0.060000 can0 0CF01300 SSI PitchAngle=0 deg RollAngle=NA PitchAngleFigureOfMerit=ERR
OUT
"$dec" --dbc "$dbc" "$tmp/in.asc" >"$tmp/got_asc.txt" 2>/dev/null
same "ASC input" "$tmp/want_asc.txt" "$tmp/got_asc.txt"

# Bad input: the file, line and reason, exit 1; --skip-errors goes on.
printf '(1700000000.000000) vcan0 18FEF100#FF005AFFFFFFFFFF\n(1700000000.010000) vcan0 18FEF100#FF0G5AFFFFFFFFFF\n(1700000000.020000) vcan0 18FEF100#FF005AFFFFFFFFFF\n' >"$tmp/bad.log"
"$dec" --dbc "$dbc" "$tmp/bad.log" >"$tmp/bad.txt" 2>"$tmp/bad_err.txt"
rc=$?
if [ "$rc" -ne 1 ] || ! grep -q "pfe_decode: $tmp/bad.log:2: bad hex: 'G' in the data" "$tmp/bad_err.txt" ||
    [ "$(wc -l <"$tmp/bad.txt")" -ne 1 ]; then
    echo "test_decode: bad line FAILED (exit $rc):"
    cat "$tmp/bad_err.txt"
    failed=$((failed + 1))
else
    echo "test_decode: bad line ok"
fi
"$dec" --dbc "$dbc" --skip-errors "$tmp/bad.log" >"$tmp/skip.txt" 2>"$tmp/skip_err.txt"
rc=$?
if [ "$rc" -ne 0 ] || [ "$(wc -l <"$tmp/skip.txt")" -ne 2 ] ||
    ! grep -q "1 x bad hex, the first: $tmp/bad.log:2: bad hex" "$tmp/skip_err.txt"; then
    echo "test_decode: --skip-errors FAILED (exit $rc):"
    cat "$tmp/skip_err.txt"
    failed=$((failed + 1))
else
    echo "test_decode: --skip-errors ok"
fi
: >"$tmp/empty.log"
"$dec" --dbc "$dbc" "$tmp/empty.log" >/dev/null 2>"$tmp/empty_err.txt"
rc=$?
if [ "$rc" -ne 1 ] || ! grep -q "empty file: no CAN frames" "$tmp/empty_err.txt"; then
    echo "test_decode: empty file FAILED (exit $rc)"
    failed=$((failed + 1))
else
    echo "test_decode: empty file ok"
fi
"$dec" --dbc "$dbc" --message NoSuchMessage "$tmp/in.log" >/dev/null 2>"$tmp/msg_err.txt"
rc=$?
if [ "$rc" -ne 1 ] || ! grep -q "no such message" "$tmp/msg_err.txt"; then
    echo "test_decode: unknown --message FAILED (exit $rc)"
    failed=$((failed + 1))
else
    echo "test_decode: unknown --message ok"
fi
# An empty DBC, and one with only a version line: nothing to decode with.
: >"$tmp/empty.dbc"
printf 'VERSION ""\n\nNS_ :\n\nBS_:\n' >"$tmp/bare.dbc"
for f in empty bare; do
    "$dec" --dbc "$tmp/$f.dbc" "$tmp/in.log" >"$tmp/dbc_out.txt" 2>"$tmp/dbc_err.txt"
    rc=$?
    if [ "$rc" -ne 1 ] || ! grep -qF "$tmp/$f.dbc: no message (BO_) in the DBC" "$tmp/dbc_err.txt" ||
        [ -s "$tmp/dbc_out.txt" ]; then
        echo "test_decode: $f DBC FAILED (exit $rc):"
        cat "$tmp/dbc_err.txt"
        failed=$((failed + 1))
    else
        echo "test_decode: $f DBC refused ok: $(cat "$tmp/dbc_err.txt")"
    fi
done
"$dec" --frobnicate >/dev/null 2>&1
rc=$?
[ "$rc" -eq 3 ] && echo "test_decode: usage error ok" ||
    { echo "test_decode: usage error exit $rc, 3 expected"; failed=$((failed + 1)); }

echo "test_decode: $failed failure(s)"
[ "$failed" -eq 0 ]

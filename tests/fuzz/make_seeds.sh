#!/bin/sh
# Writes the committed seed corpora of the fuzz targets (tests/fuzz/corpus/)
# from the bundled logs: the first 50 lines of each, in the formats each
# parser reads, and the start of a drive as fuzz_ecu operations.
#
#   tests/fuzz/make_seeds.sh DRIVE_LOG ECU_SEED
#
# DRIVE_LOG: build/e2e/payload/drive.log; ECU_SEED: the ecu_seed program
# (tests/fuzz/ecu_seed.c). Needs gzip, awk and can-utils' log2asc. The
# DBC's seeds are can_dbc/pfe.dbc itself, copied by mk/fuzz.mk at each run,
# and the hand-written tests/fuzz/corpus/dbc/features.dbc (the sections
# pfe.dbc does not use), which this script leaves as it is.
set -eu

drive=$1
ecu_seed=$2
dir=tests/fuzz/corpus
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export TZ=UTC LC_ALL=C

head -n 50 "$drive" > "$tmp/drive.log"
for road in flat uphill hilly; do
    gzip -dc "sim_host/data/logs/$road.log.gz" | head -n 50 > "$tmp/$road.log"
done

# candump's printed view (-t a) of a candump log
printed() {
    awk '{
        split($3, f, "#"); id = f[1]; data = f[2]; n = length(data) / 2; bytes = "";
        for (k = 0; k < n; k++) bytes = bytes (k ? " " : "") substr(data, 2 * k + 1, 2);
        printf "%s  %s  %s   [%d]  %s\n", $1, $2, id, n, bytes
    }' "$1"
}

rm -rf "$dir/canlog" "$dir/replay" "$dir/capture" "$dir/ecu" "$dir/nvm"
mkdir -p "$dir/canlog" "$dir/replay" "$dir/capture" "$dir/ecu" "$dir/nvm"

# canlog: byte 0 is the format (0 auto, 1 log, 2 printed, 4 asc) | 8 skip mode
log2asc -I "$tmp/drive.log" -O "$tmp/drive.asc" vcan0
{ printf '\000'; cat "$tmp/drive.log"; } > "$dir/canlog/drive_log"
{ printf '\002'; printed "$tmp/drive.log"; } > "$dir/canlog/drive_printed"
{ printf '\004'; cat "$tmp/drive.asc"; } > "$dir/canlog/drive_asc"
{ printf '\010'; cat "$tmp/hilly.log"; } > "$dir/canlog/hilly_log_skip"

# replay: 256 bytes a read, no read or write failure, a frame sent every
# 8 log frames; the clock from frame to frame, or in 10 ms steps
{ printf '\377\010\000'; cat "$tmp/drive.log"; } > "$dir/replay/drive"
{ printf '\017\000\012'; cat "$tmp/uphill.log"; } > "$dir/replay/uphill_10ms"

# capture: the logs as they are
cp "$tmp/drive.log" "$dir/capture/drive"
cp "$tmp/flat.log" "$dir/capture/flat"

# ecu: the drive's first 250 frames (a whole grade preview) and 15 s more;
# the hilly road's first 120 frames and 10 s more
"$ecu_seed" "$drive" 250 1500 "$dir/ecu/drive_start"
gzip -dc sim_host/data/logs/hilly.log.gz | head -n 120 > "$tmp/hilly120.log"
"$ecu_seed" "$tmp/hilly120.log" 120 1000 "$dir/ecu/hilly_start"

# nvm: flags 0x0F (both slots: magic and CRC set by the target), then two
# records "PFN1", sequence, own uL, platoon uL (little endian), CRC space
le() { # a hex number as little-endian bytes
    hex=$1 out=""
    while [ -n "$hex" ]; do
        out="$out\\x${hex#"${hex%??}"}"
        hex=${hex%??}
    done
    env printf "$out"
}
rec() { # sequence (8 hex digits), own and platoon uL (16 each)
    printf 'PFN1'; le "$1"; le "$2"; le "$3"; printf '\000\000\000\000'
}
{ printf '\017'; rec 00000007 0000000000000064 00000000000001F4;
  rec 00000008 0000000000000096 00000000000002BC; } > "$dir/nvm/two_slots"
{ printf '\017'; rec FFFFFFFF 00000000000F4240 00000000004C4B40;
  rec 00000000 00000000000F4241 00000000004C4B41; } > "$dir/nvm/sequence_wraps"
{ printf '\017'; rec 00000001 FFFFFFFFFFFFFFFF 0000A7C5AC471B47;
  rec 00000002 00000003D4A2B3F8 FFFFFFFFFFFFFFFF; } > "$dir/nvm/fuel_at_limits"
wc -c "$dir"/*/* | sort -n | tail -n 3

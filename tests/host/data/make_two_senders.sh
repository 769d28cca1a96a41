#!/bin/sh
# Writes tests/host/data/two_senders.txt: a capture as a bench records one
# on a truck (candump -t z's printed form), for the judge's tests
# (tests/host/run_report_test.sh):
#   - 12 s from the middle of the bundled hilly drive (60 to 72 s): no
#     address claims, no SSI (no slope sensor), no PFE_PlatoonConfig;
#   - CCVS1 from two senders: the engine (SA 0x00, the drive's speeds) and
#     the cab controller (SA 0x31, every 100 ms, speed not available);
#   - 200 PGNs the module does not read (0xFE80-0xFED7 and 0xFD10-0xFD7F
#     from SA 0x17, each every 4 s);
#   - the module's frames (SA 0x8C) as pfe_ecu_replay answers those inputs;
#   - the engine's LFE1 (SA 0x00), 40 ms before each of the module's
#     PFE_OwnFuel frames: 1.25 times the module's own-truck rate (raw,
#     rounded to the 0.05 L/h step), not available where the module's is,
#     so that the judge's figures are known: r = 1, integrated ratio 0.8
#     to within the rounding; the module's LFE1 and HRLFC are left out, as
#     the module leaves them to the engine on such a bus.
#
#   tests/host/data/make_two_senders.sh PFE_ECU_REPLAY HILLY.log OUT
set -eu
replay=$1 hilly=$2 out=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
awk '$1 >= "(1700000060.000000)" && $1 < "(1700000072.000000)" && $3 ~ /^18FEF100#/ {
         print
         t = substr($1, 2, 17) + 0.004
         printf "(%.6f) %s 18FEF131#FFFFFFFFFFFFFFFF\n", t, $2 }
     END {
         for (k = 0; k < 200; k++) {
             pgn = (k < 88) ? 65152 + k : 64784 + (k - 88)
             for (s = 60; s < 72; s += 4) {
                 t = 1700000000 + s + k * 0.019 + 0.001
                 printf "(%.6f) vcan0 18%04X17#%02X%02X%02X%02XFFFFFFFF\n", t, pgn, k, s, (k * 7) % 256, (k * 13) % 256
             }
         }
     }' "$hilly" | sort -s -k1,1 >"$tmp/inputs.log"
"$replay" --log "$tmp/inputs.log" --record "$tmp/record.log" >/dev/null
# The engine's LFE1 from the module's PFE_OwnFuel; the module's LFE1 and HRLFC left out.
awk 'function hex(s,  v, i) { for (i = 1; i <= length(s); i++) v = v * 16 + index("0123456789ABCDEF", substr(s, i, 1)) - 1; return v }
     { print }
     $3 ~ /^18FF058C#/ {
         d = substr($3, 10)
         raw = hex(substr(d, 3, 2) substr(d, 1, 2))
         if (raw >= 64256) { e = "FFFF" } else { v = int(raw * 1.25 + 0.5); e = sprintf("%02X%02X", v % 256, int(v / 256)) }
         t = substr($1, 2, 17) - 0.040
         printf "(%.6f) %s 18FEF200#%sFFFFFFFFFFFF\n", t, $2, e }' "$tmp/record.log" |
    grep -v ' 18FEF28C#' | grep -v ' 18FD098C#' | sort -s -k1,1 |
    awk '{ t = substr($1, 2, 17) - 1700000060; split($3, a, "#"); d = a[2]; s = ""
           for (i = 1; i <= length(d); i += 2) s = s " " substr(d, i, 2)
           printf "(%03d.%06d)  %s  %8s   [%d] %s\n", int(t), int((t - int(t)) * 1000000 + 0.5), $2, a[1], length(d) / 2, s }' \
        >"$out"

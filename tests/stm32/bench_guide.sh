#!/bin/sh
# The bench guide's commands (docs/stm32_bench.md) that run without a board
# or a CAN interface:
#   - the build's outputs exist, the vector table is at 0x08000000, and the
#     .hex programs nothing in the NVM sectors 1 and 2 (0x08004000 ..
#     0x0800BFFF) while the .bin spans them;
#   - openocd parses the guide's interface and target configuration
#     (-c shutdown: stops before looking for a probe), and with
#     "init; exit" gets as far as the probe (none here: "open failed");
#   - st-flash runs;
#   - the guide's replay command with --dry-run (its first second) sends
#     nothing and prints frames for can0;
#   - pfe_record and run_report answer --help.
#
#   tests/stm32/bench_guide.sh STM32_OUT HOST_BIN DRIVE_LOG
set -eu
out=$1
bin=$2
log=$3
fail() { echo "bench-guide: FAIL: $*" >&2; exit 1; }

for f in pfe_stm32.elf pfe_stm32.hex pfe_stm32.bin; do
    [ -s "$out/$f" ] || fail "$out/$f missing"
done
vma=$(arm-none-eabi-objdump -h "$out/pfe_stm32.elf" | awk '$2 == ".isr_vector" { print $4 }')
[ "$vma" = "08000000" ] || fail ".isr_vector at $vma, not 08000000"
# Intel hex: type 04 records give the upper 16 bits, type 00 data at offsets.
python3 - "$out/pfe_stm32.hex" <<'PY' || fail "the .hex writes into the NVM sectors"
import sys
upper = 0
lo, hi = 0x08004000, 0x0800C000
for line in open(sys.argv[1]):
    n, off, kind = int(line[1:3], 16), int(line[3:7], 16), int(line[7:9], 16)
    if kind == 4:
        upper = int(line[9:13], 16) << 16
    elif kind == 0:
        a = upper + off
        if a < hi and a + n > lo:
            print("bench-guide: data at 0x%08x" % a)
            sys.exit(1)
PY
size=$(wc -c < "$out/pfe_stm32.bin")
[ "$size" -gt $((0x0800C000 - 0x08000000)) ] || fail ".bin of $size bytes does not span the NVM sectors"
[ "$size" -lt $((0x0800C000 - 0x08000000 + 49152)) ] || fail ".bin of $size bytes: more than the image"
echo "bench-guide: image: vectors at 0x08000000, .hex clear of the NVM sectors, .bin $size bytes"

openocd -f interface/stlink.cfg -f target/stm32f4x.cfg -c shutdown >"$out/openocd_cfg.txt" 2>&1 ||
    { cat "$out/openocd_cfg.txt"; fail "openocd does not accept the configuration"; }
grep -q "shutdown command invoked" "$out/openocd_cfg.txt" || fail "openocd: no shutdown"
if openocd -f interface/stlink.cfg -f target/stm32f4x.cfg -c "init; exit" >"$out/openocd_init.txt" 2>&1; then
    echo "bench-guide: openocd found a probe (a board is attached)"
else
    grep -q "open failed" "$out/openocd_init.txt" ||
        { cat "$out/openocd_init.txt"; fail "openocd failed otherwise than for want of a probe"; }
    echo "bench-guide: openocd: configuration accepted; no ST-LINK attached, as expected here"
fi
st-flash --version >/dev/null 2>&1 || fail "st-flash does not run"

"$bin/pfe_replay" --dry-run --allow-real-bus --end 1 -I "$log" can0=vcan0 >"$out/replay_dry.txt" 2>"$out/replay_dry.err" ||
    { cat "$out/replay_dry.err"; fail "pfe_replay --dry-run failed"; }
frames=$(grep -c '^([0-9]*\.[0-9]*) can0 [0-9A-F]*#' "$out/replay_dry.txt" || true)
others=$(grep -vc ' can0 ' "$out/replay_dry.txt" || true)
[ "$frames" -gt 0 ] && [ "$others" -eq 0 ] || fail "dry run: $frames frames for can0, $others other lines"
grep -q "^pfe_replay: 0 sent, $frames written to stdout" "$out/replay_dry.err" ||
    { cat "$out/replay_dry.err"; fail "dry run: summary does not say 0 sent, $frames written"; }
echo "bench-guide: pfe_replay --dry-run: 0 sent, $frames frames for can0 in the first second"

"$bin/pfe_record" --help >/dev/null 2>&1 || fail "pfe_record --help"
"$bin/run_report" --help >/dev/null 2>&1 || fail "run_report --help"
echo "bench-guide: all passed"

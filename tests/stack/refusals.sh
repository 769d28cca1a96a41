#!/bin/sh
# Shows that the worst-case stack check can fail: run exactly as `make
# stack-check` runs it, it must refuse
#   1. the ECU image when no indirect call has its targets listed,
#   2. a call graph with a cycle (an edge from a leaf back to main added to
#      the self-check image's graph),
#   3. the ECU image when a function whose address it stores (read_host,
#      main_ecu.c's semihosting read, set as the replay backend's callback)
#      is listed as no indirect call's target,
# and fail
#   4. the self-check image linked with a 512-byte stack
#      (STACK_OUT/small/pfe_mps2.elf), which its worst case exceeds.
#
#   tests/stack/refusals.sh STACK_OUT M4_OUT CHECK_COMMAND...
#
# CHECK_COMMAND is scripts/stack_check.py with its --indirect option.

set -u

out=$1
m4=$2
shift 2
tmp=${TMPDIR:-/tmp}/stack_refusals.$$
mkdir -p "$tmp"
trap 'rm -rf "$tmp"' EXIT

# expect NAME PATTERN COMMAND...: COMMAND exits 1 and prints PATTERN.
expect() {
    name=$1
    pattern=$2
    shift 2
    "$@" >"$tmp/out" 2>&1
    rc=$?
    if [ "$rc" -ne 1 ] || ! grep -q "$pattern" "$tmp/out"; then
        cat "$tmp/out"
        echo "stack-refusals: $name: expected exit 1 and \"$pattern\", got exit $rc"
        exit 1
    fi
    echo "stack-refusals: $name: $(grep -m1 "$pattern" "$tmp/out" | sed 's/^stack: //')"
}

# 1. The same check with an empty list of indirect targets.
: >"$tmp/none.txt"
expect "no indirect targets" "refused: indirect call at hal/replay/hal_replay.c" \
    "$@" --indirect "$tmp/none.txt" --elf "$m4/pfe_ecu_mps2.elf" \
    --ci "$out"/pfe_ecu_mps2/*.ci

# 2. Recursion: line_u64 calls main again.
ci=$(ls "$out"/pfe_mps2/*.ci)
prefix=$(sed -n 's/^node: { title: "\([^"]*:\)main".*/\1/p' "$ci")
cp "$ci" "$tmp/cycle.ci"
echo "edge: { sourcename: \"${prefix}line_u64\" targetname: \"${prefix}main\" }" >>"$tmp/cycle.ci"
expect "recursion" "refused: recursion: .*main > line_u64 > main" \
    "$@" --elf "$m4/pfe_mps2.elf" --ci "$tmp/cycle.ci"

# 3. A stored address no entry lists: bus->read( given write_host only.
sed -e 's/^\(hal\/replay\/hal_replay.c  *bus->read(  *\)read_host$/\1write_host/' \
    scripts/stack_indirect.txt >"$tmp/unlisted.txt"
if cmp -s scripts/stack_indirect.txt "$tmp/unlisted.txt"; then
    echo "stack-refusals: stored address: scripts/stack_indirect.txt has no 'bus->read(  read_host' entry to change"
    exit 1
fi
expect "stored address" "refused: the address of read_host is stored in the image" \
    "$@" --indirect "$tmp/unlisted.txt" --elf "$m4/pfe_ecu_mps2.elf" \
    --ci "$out"/pfe_ecu_mps2/*.ci

# 4. A stack smaller than the worst case.
expect "512-byte stack" "FAILED: the worst case exceeds the stack" \
    "$@" --elf "$out/small/pfe_mps2.elf" --ci "$out"/small/*.ci
echo "stack-refusals: the check refuses or fails in all four cases, as it should"

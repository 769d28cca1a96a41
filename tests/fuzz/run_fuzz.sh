#!/bin/sh
# Runs one libFuzzer target: its regression inputs first, then fuzzing for a
# while from its seeds, and prints one summary line.
#
#   tests/fuzz/run_fuzz.sh BIN NAME SECONDS OUT [SEED_DIR...]
#
# BIN       the fuzz target (mk/fuzz.mk builds build/fuzz/fuzz_NAME)
# NAME      its name: seeds in tests/fuzz/corpus/NAME, regression inputs in
#           tests/fuzz/regress/NAME, dictionary tests/fuzz/NAME.dict if any
# SECONDS   fuzzing time (libFuzzer -max_total_time)
# OUT       build folder: OUT/corpus/NAME (the growing corpus, kept between
#           runs), OUT/crash/NAME (crashes, kept too: the summary counts this
#           run's), OUT/NAME.log (libFuzzer's output)
# SEED_DIR  more seed folders (read only)
#
# Environment: FUZZ_MAX_LEN, the longest input tried (4096 bytes).
#
# Summary line, from libFuzzer's own figures (its last status line and
# -print_final_stats):
#   fuzz: NAME: 123456 runs in 12 s, cov 555 of 1542 edges, ft 2734, corpus 1245 inputs,
#         3 regression inputs ok, 0 crashes
# (cov: edges reached, of the binary's instrumented edges, harness included;
# ft: libFuzzer's features, edges with hit counts)
#
# Exit status 0, or 1 when a regression input or a fuzzing input crashed
# (the input is named: commit it under tests/fuzz/regress/NAME with the fix),
# 2 on bad arguments.
set -u

if [ $# -lt 4 ]; then
    echo "usage: run_fuzz.sh BIN NAME SECONDS OUT [SEED_DIR...]" >&2
    exit 2
fi
bin=$1 name=$2 seconds=$3 out=$4
shift 4
here=tests/fuzz
corpus=$out/corpus/$name
crash=$out/crash/$name
log=$out/$name.log
mkdir -p "$corpus" "$crash"

# Regression inputs: each run once; any crash fails.
nreg=0
if [ -d "$here/regress/$name" ]; then
    regs=$(find "$here/regress/$name" -type f | sort)
    if [ -n "$regs" ]; then
        nreg=$(echo "$regs" | wc -l)
        # shellcheck disable=SC2086 # one argument per file, names without blanks
        if ! "$bin" -runs=1 $regs > "$out/$name.regress.log" 2>&1; then
            echo "fuzz: $name: a regression input crashes again:" >&2
            grep -E "Running:|invariant|ERROR|SUMMARY" "$out/$name.regress.log" | tail -n 8 >&2
            exit 1
        fi
    fi
fi

crashes_before=$(find "$crash" -type f | wc -l)
[ -d "$here/corpus/$name" ] && set -- "$here/corpus/$name" "$@"
dict=""
[ -f "$here/$name.dict" ] && dict="-dict=$here/$name.dict"
# -timeout: an input running 10 s is a hang; -max_len (FUZZ_MAX_LEN, 4096
# unless set) keeps inputs a few KB, the seeds' size.
# shellcheck disable=SC2086 # $dict is one option or nothing
"$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len="${FUZZ_MAX_LEN:-4096}" \
    -print_final_stats=1 -artifact_prefix="$crash/" $dict \
    "$corpus" "$@" > "$log" 2>&1
rc=$?

runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
status=$(grep -E '^#[0-9]+.*cov: ' "$log" | tail -n 1)
cov=$(echo "$status" | sed -n 's/.* cov: \([0-9]*\).*/\1/p')
ft=$(echo "$status" | sed -n 's/.* ft: \([0-9]*\).*/\1/p')
edges=$(sed -n 's/.*(\([0-9]*\) inline 8-bit counters).*/\1/p' "$log" | head -n 1)
inputs=$(find "$corpus" -type f | wc -l)
crashes=$(( $(find "$crash" -type f | wc -l) - crashes_before ))
echo "fuzz: $name: ${runs:-0} runs in $seconds s, cov ${cov:-0} of ${edges:-?} edges, ft ${ft:-0}," \
     "corpus $inputs inputs, $nreg regression inputs ok, $crashes crashes"
if [ $rc -ne 0 ]; then
    echo "fuzz: $name: libFuzzer stopped (exit $rc):" >&2
    grep -E "invariant|ERROR|SUMMARY|Test unit written" "$log" | tail -n 8 >&2
    exit 1
fi
exit 0

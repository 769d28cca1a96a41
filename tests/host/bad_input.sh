#!/bin/sh
# Bad input to every host tool, against its ASan and UBSan build (make san).
#
#   tests/host/bad_input.sh TOOLS_DIR WORK_DIR DBC
#
# For each tool and each kind of bad input (a missing file, an empty file, a
# binary file, one huge line, a directory, bad numbers on the command line,
# an empty argument) the tool must end by itself within its time limit,
# without a sanitizer report and without a signal; when it fails, it says why
# on stderr. A missing file or a directory where a file is read must fail.
# Prints one line per run and a summary; exits 1 when any run breaks a rule.
# No tool sends a frame: pfe_replay runs --dry-run, the others never open a
# bus or fail before they do (this kernel has no CAN).

set -u

if [ $# -ne 3 ]; then
    echo "usage: $0 TOOLS_DIR WORK_DIR DBC" >&2
    exit 2
fi
T=$1
W=$2
DBC=$3
LIMIT_S=${BAD_INPUT_TIMEOUT_S:-60}

mkdir -p "$W"
rm -rf "${W:?}"/in "$W"/out
mkdir -p "$W/in/dir" "$W/out"
: >"$W/in/empty"
# A binary file, the same on every run: an ELF of the tools themselves.
cp "$T/roadgen" "$W/in/binary"
# One line of 4 MB: digits, so that a number parser is the one that meets it.
head -c 4000000 /dev/zero | tr '\0' '7' >"$W/in/huge"
printf '(0.000000) vcan0 18FEF100#FF005AFFFFFFFFFF\n' >"$W/in/one.log"
MISSING=$W/in/no-such-file
FLAT=sim_host/data/roads/flat.csv
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:exitcode=99
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:exitcode=98

runs=0
bad=0
n_fail_exit=0
n_zero_exit=0

# check NAME MUST_FAIL CMD...   (MUST_FAIL 1: exit 0 breaks the rules)
check() {
    cname=$1
    must_fail=$2
    shift 2
    runs=$((runs + 1))
    out=$W/out/$runs.out
    err=$W/out/$runs.err
    timeout -k 5 "$LIMIT_S" "$@" >"$out" 2>"$err" </dev/null
    rc=$?
    why=""
    if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then
        why="did not end within ${LIMIT_S} s"
    elif grep -q -e 'AddressSanitizer' -e 'LeakSanitizer' -e 'runtime error:' "$err"; then
        why="sanitizer report"
    elif [ "$rc" -ge 128 ]; then
        why="killed by signal $((rc - 128))"
    elif [ "$rc" -ne 0 ] && [ ! -s "$err" ]; then
        why="exit $rc without a word on stderr"
    elif [ "$rc" -eq 0 ] && [ "$must_fail" -eq 1 ]; then
        why="exit 0 on input it cannot have read"
    fi
    if [ "$rc" -eq 0 ]; then
        n_zero_exit=$((n_zero_exit + 1))
    else
        n_fail_exit=$((n_fail_exit + 1))
    fi
    msg=$(head -n 1 "$err" | cut -c 1-100)
    if [ -n "$why" ]; then
        bad=$((bad + 1))
        echo "bad-input: FAIL $cname: $why (exit $rc)"
        head -n 20 "$err" | sed 's/^/    /'
    else
        echo "bad-input: ok   $cname: exit $rc${msg:+: $msg}"
    fi
}

# file_cases NAME PREFIX... -- SUFFIX...: the tool with each bad file between.
file_cases() {
    fname=$1
    shift
    pre=""
    while [ "$1" != "--" ]; do
        pre="$pre $1"
        shift
    done
    shift
    post="$*"
    # shellcheck disable=SC2086
    check "$fname missing file" 1 $pre "$MISSING" $post
    # shellcheck disable=SC2086
    check "$fname directory" 1 $pre "$W/in/dir" $post
    # shellcheck disable=SC2086
    check "$fname empty file" 0 $pre "$W/in/empty" $post
    # shellcheck disable=SC2086
    check "$fname binary file" 0 $pre "$W/in/binary" $post
    # shellcheck disable=SC2086
    check "$fname huge line" 0 $pre "$W/in/huge" $post
}

# number_cases NAME OPTION PREFIX... -- SUFFIX...: OPTION with bad numbers.
number_cases() {
    nname=$1
    opt=$2
    shift 2
    pre=""
    while [ "$1" != "--" ]; do
        pre="$pre $1"
        shift
    done
    shift
    post="$*"
    for v in abc -1 1e999 99999999999999999999999 0x 1.5.5; do
        # shellcheck disable=SC2086
        check "$nname $opt '$v'" 1 $pre "$opt" "$v" $post
    done
    # shellcheck disable=SC2086
    check "$nname $opt ''" 1 $pre "$opt" "" $post
    # shellcheck disable=SC2086
    check "$nname $opt (no value)" 1 $pre "$opt"
}

O=$W/out

file_cases platoon_sim "$T/platoon_sim" --road --
number_cases platoon_sim --vehicles "$T/platoon_sim" --road "$FLAT" --

file_cases drivegen "$T/drivegen" --road -- --out "$O/drive.log"
number_cases drivegen --set-speed-kmh "$T/drivegen" --segment 100:0 --out "$O/drive.log" --
number_cases drivegen --speed-phase-ms "$T/drivegen" --segment 100:0 --out "$O/drive.log" --
check "drivegen --speed-phase-ms 100" 1 "$T/drivegen" --segment 100:0 --speed-phase-ms 100 --out "$O/drive.log"
check "drivegen --segment 'x:y'" 1 "$T/drivegen" --segment x:y --out "$O/drive.log"
check "drivegen --out directory" 1 "$T/drivegen" --segment 100:0 --out "$W/in/dir"

file_cases road2c "$T/road2c" flat -- "$O/road.c"
check "road2c out directory" 1 "$T/road2c" flat "$FLAT" "$W/in/dir"

file_cases dbc2c "$T/dbc2c" -- "$O/pfe_dbc.c"
check "dbc2c out directory" 1 "$T/dbc2c" "$DBC" "$W/in/dir"

check "roadgen unknown name" 1 "$T/roadgen" no-such-road
check "roadgen --out directory" 1 "$T/roadgen" flat --out "$W/in/dir"
check "routegen unknown name" 1 "$T/routegen" no-such-route
check "routegen --out directory" 1 "$T/routegen" hilly --out "$W/in/dir"

file_cases run_report "$T/run_report" --
number_cases run_report --warmup-s "$T/run_report" "$W/in/empty" --

file_cases pfe_replay "$T/pfe_replay" --dry-run -I --
number_cases pfe_replay -g "$T/pfe_replay" --dry-run -I "$W/in/empty" --
number_cases pfe_replay --spin-us "$T/pfe_replay" --dry-run -I "$W/in/empty" --

file_cases "pfe_decode --dbc" "$T/pfe_decode" --dbc -- "$W/in/one.log"
file_cases "pfe_decode log" "$T/pfe_decode" --dbc "$DBC" --

file_cases pfe_ecu_replay "$T/pfe_ecu_replay" --log --
number_cases pfe_ecu_replay --address "$T/pfe_ecu_replay" --log "$W/in/empty" --
number_cases pfe_ecu_replay --save-interval-ms "$T/pfe_ecu_replay" --log "$W/in/empty" --

file_cases platoon_compare "$T/platoon_compare" --road --
number_cases platoon_compare --vehicles "$T/platoon_compare" --road "$FLAT" --

file_cases route_choice "$T/route_choice" -- "$FLAT"
number_cases route_choice --vehicles "$T/route_choice" "$FLAT" "$FLAT" --

number_cases sensitivity --vehicles "$T/sensitivity" --no-plot --out "$O/sens" --
check "sensitivity --out a file" 1 "$T/sensitivity" --no-plot --out "$W/in/empty" --vehicles 0

number_cases pfe_record -n "$T/pfe_record" -- vcan0
number_cases pfe_record --rcvbuf "$T/pfe_record" -- vcan0
check "pfe_record empty interface name" 1 "$T/pfe_record" ""
check "pfe_record -o directory" 1 "$T/pfe_record" -o "$W/in/dir" vcan0

check "pfe_ecu empty interface name" 1 "$T/pfe_ecu" --iface "" --nvm "$O/nvm.bin" --duration-s 1
number_cases pfe_ecu --address "$T/pfe_ecu" --iface vcan0 --nvm "$O/nvm.bin" --
number_cases pfe_ecu --duration-s "$T/pfe_ecu" --iface vcan0 --nvm "$O/nvm.bin" --

echo "bad-input: $runs runs, $bad broke a rule ($n_fail_exit ended with an error, $n_zero_exit with exit 0)"
[ "$bad" -eq 0 ]

#!/bin/sh
# Foreign-truck logs (sim_host/tools/truckgen.c) through the firmware on the host
# (pfe_ecu_replay), judged by sim_host/tools/truck_judge.c:
#   - a 12 t and a 60 t truck, no SSI, two senders of CCVS1 and LFE1, the
#     engine's LFE1 and HRLFC, 220 unrelated PGNs, mid-drive, no claims:
#     the printed form and the -L form hold the same drive; replayed (as
#     written once pfe_ecu_replay reads the printed form, else in -L form)
#     with the truck's calibration and with the default one, the estimate is
#     available in >= 95 % of PFE_OwnFuel frames after 10 s, GradeSource 2
#     (assumed flat), the module never sends LFE1/HRLFC while the engine does;
#     with the truck's calibration its own fuel used is within 5 % of the
#     truth (truckgen --truth); with the default one the error is reported
#     (what identification from the engine's LFE1 has to correct);
#   - the 12 t truck with SSI: GradeSource 0; with VDS altitude over the
#     hilly road every 100 ms: GradeSource 1; every 1 s: available;
#   - the engine's LFE1 stopping after 120 s: still available;
#   - identification (docs/identification.md): the 12 t and the 60 t truck
#     over rolling speeds (50 to 85 km/h, a change every 15 to 25 s) for
#     the first 180 s of log, the engine's LFE1 only until then, replayed
#     with the default (40 t) calibration: at 180 s the mass is identified
#     and converged, within 15 % of the truth, and the module's own fuel
#     over the next 5 minutes is within 10 % of the truth's; the same drive
#     with no engine LFE1 at all gives the contrast (bench:
#     identify_*_pct_12t, identify_off_*_pct_12t, ... for 60t);
#   - hostile variants (own-address spoof, speed jumps, random payloads) of
#     the 12 t truck with SSI and of the 60 t truck without: every valid rate
#     the module sends is the clean run's, but for one frame per burst, and
#     PFE_Status counts every spoofed frame as a conflict and every speed
#     jump as a rejection (random payloads: rejections, at most one each).
# Random payloads are judged too; while HOSTILE_RANDOM_XFAIL is 1 their
# failure is reported as a known one (the firmware takes a random speed
# that happens to lie within the plausible change of the last one) and does
# not fail the test; should they pass then, the test fails so that the flag
# is cleared.
#
#   tests/host/foreign_trucks.sh HOST_TOOLS_DIR TRUCKS_DIR OUTDIR
set -u
tools=$1 trucks=$2 out=$3
xfail_random=${HOSTILE_RANDOM_XFAIL:-1}
mkdir -p "$out"
fail=0

# sh has no local variables: each function's own are prefixed with its name.
gen() { # NAME TRUCK [truckgen options...]: OUT/NAME.$ext (in the form replayed)
    gen_name=$1 gen_truck=$2
    shift 2
    "$tools/truckgen" --calib "$trucks/truck$gen_truck.cal" --format "$form" \
        --out "$out/$gen_name.$ext" "$@" 2> "$out/$gen_name.gen.err" ||
        { echo "foreign: truckgen $gen_name failed: $(cat "$out/$gen_name.gen.err")"; fail=1; }
}

replay() { # NAME LOG [--calib FILE]: OUT/NAME.rec
    rp_name=$1 rp_log=$2
    shift 2
    "$tools/pfe_ecu_replay" --log "$rp_log" --record "$out/$rp_name.rec" "$@" \
        > "$out/$rp_name.replay.txt" 2> "$out/$rp_name.replay.err" ||
        { echo "foreign: replay $rp_name failed: $(cat "$out/$rp_name.replay.err")"; fail=1; }
}

judge() { # truck_judge arguments; a failure fails the test
    "$tools/truck_judge" "$@" | tee -a "$out/bench.txt" | sed 's/^/foreign: /'
    # shellcheck disable=SC2181
    [ "$(tail -n 1 "$out/bench.txt" | sed 's/.*: //')" = pass ] || fail=1
}

: > "$out/bench.txt"
# The logs are replayed as written (candump's printed form) once
# pfe_ecu_replay reads it; until then in the -L form of the same drive.
"$tools/truckgen" --calib "$trucks/truck12t.cal" --out "$out/probe.txt" --profile 0:1,20:4 \
    --start-s 0 2> /dev/null
if "$tools/pfe_ecu_replay" --log "$out/probe.txt" > /dev/null 2>&1; then
    form=printed ext=txt
else
    form=log ext=log
    echo "foreign: pfe_ecu_replay does not read candump's printed form yet: replaying the -L form"
fi
for t in 12t 60t; do
    "$tools/truckgen" --calib "$trucks/truck$t.cal" --format printed --out "$out/$t.txt" 2> /dev/null
    "$tools/truckgen" --calib "$trucks/truck$t.cal" --format log --out "$out/$t.log" \
        --truth "$out/$t.truth.csv" 2> /dev/null
    "$tools/truck_judge" same "$out/$t.txt" "$out/$t.log" | sed "s/^/foreign: $t: /" || fail=1
    head -n 3 "$out/$t.txt" | sed "s/^/foreign: $t printed: /"
    replay "$t" "$out/$t.$ext" --calib "$trucks/truck$t.cal"
    judge avail "$out/$t.rec" --name "$t" --grade-source 2 --truth "$out/$t.truth.csv" \
        --max-fuel-err-pct 5
    replay "$t-default" "$out/$t.$ext"
    judge avail "$out/$t-default.rec" --name "${t}_default_calib" --grade-source 2 \
        --truth "$out/$t.truth.csv"
done

gen 12t-ssi 12t --ssi
replay 12t-ssi "$out/12t-ssi.$ext" --calib "$trucks/truck12t.cal"
judge avail "$out/12t-ssi.rec" --name 12t_ssi --grade-source 0

# VDS altitude over the hilly road, at the DBC's 100 ms (GradeSource 1) and
# at J1939-71's 1 s (the module's VDS rule, 100 ms, times it out: flat).
gen 12t-vds 12t --vds --vds-period-ms 100 --road "$trucks/../roads/hilly.csv"
replay 12t-vds "$out/12t-vds.$ext" --calib "$trucks/truck12t.cal"
judge avail "$out/12t-vds.rec" --name 12t_vds --grade-source 1
gen 12t-vds1s 12t --vds --road "$trucks/../roads/hilly.csv"
replay 12t-vds1s "$out/12t-vds1s.$ext" --calib "$trucks/truck12t.cal"
judge avail "$out/12t-vds1s.rec" --name 12t_vds_1s

# The engine's LFE1 stops after 120 s: the estimate goes on. (The cab
# controller's LFE1, not available, goes on too: the module still hears
# another sender of LFE1 and does not send its own.)
gen 60t-lfe1-stop 60t --engine-fuel-stop-s 120
replay 60t-lfe1-stop "$out/60t-lfe1-stop.$ext" --calib "$trucks/truck60t.cal"
judge avail "$out/60t-lfe1-stop.rec" --name 60t_lfe1_stop --grade-source 2

# Identification from the engine's LFE1, then 5 minutes without it; the
# module is not told which truck it is (default calibration).
id_profile=0:3,70:25,50:15,80:20,55:15,85:20,60:15,80:20,50:15,75:20,85:60,60:30,80:60,50:30,85:60,70:60,0:20,60:40
id_stop_s=180
for t in 12t 60t; do
    gen "$t-ident" "$t" --profile "$id_profile" --engine-fuel-stop-s "$id_stop_s" \
        --truth "$out/$t-ident.truth.csv"
    replay "$t-ident" "$out/$t-ident.$ext"
    tail -n 1 "$out/$t-ident.replay.txt" | sed "s/^/foreign: $t-ident: /"
    judge identify "$out/$t-ident.rec" --name "$t" --truth "$out/$t-ident.truth.csv" \
        --from "$id_stop_s" --for 300 --mass "${t%t}000" --max-mass-err-pct 15 --max-fuel-err-pct 10
    gen "$t-ident-off" "$t" --profile "$id_profile" --engine-fuel-stop-s 0
    replay "$t-ident-off" "$out/$t-ident-off.$ext"
    judge identify "$out/$t-ident-off.rec" --name "$t" --truth "$out/$t-ident.truth.csv" \
        --from "$id_stop_s" --for 300 --mass "${t%t}000" --off
done

hostile() { # TRUCK CLEAN KIND EXPECT [truckgen options...]
    h_truck=$1 h_clean=$2 h_kind=$3 h_expect=$4
    shift 4
    h_name=$h_clean-$h_kind
    gen "$h_name" "$h_truck" --hostile "$h_kind" "$@"
    h_bursts=$(sed -n 's/^truckgen: \([0-9]*\) hostile bursts, .*/\1/p' "$out/$h_name.gen.err")
    h_frames=$(sed -n 's/^truckgen: .* bursts, \([0-9]*\) hostile frames$/\1/p' "$out/$h_name.gen.err")
    # every spoofed frame is a conflict, every speed jump a rejection; of
    # random payloads, those that pass by chance are not
    h_exact=--exact
    [ "$h_kind" = random ] && h_exact=
    replay "$h_name" "$out/$h_name.$ext" --calib "$trucks/truck$h_truck.cal"
    if [ "$h_kind" = random ] && [ "$xfail_random" = 1 ]; then
        "$tools/truck_judge" hostile "$out/$h_clean.rec" "$out/$h_name.rec" --bursts "${h_bursts:-0}" \
            --name "$(echo "$h_name" | tr - _)" --expect "$h_expect" --frames "${h_frames:-0}" | tee -a "$out/bench.txt" |
            sed 's/^/foreign: /'
        if [ "$(tail -n 1 "$out/bench.txt" | sed 's/.*: //')" = pass ]; then
            echo "foreign: $h_name: passes now: clear HOSTILE_RANDOM_XFAIL (mk/truck.mk)"
            fail=1
        else
            echo "foreign: $h_name: KNOWN FAILURE (HOSTILE_RANDOM_XFAIL=1): a random CCVS1 speed" \
                "within the plausible change of the last one is taken as valid"
        fi
        return
    fi
    # shellcheck disable=SC2086
    judge hostile "$out/$h_clean.rec" "$out/$h_name.rec" --bursts "${h_bursts:-0}" \
        --name "$(echo "$h_name" | tr - _)" --expect "$h_expect" --frames "${h_frames:-0}" $h_exact
}
for kind in spoof:conflicts jump:rejected random:rejected; do
    hostile 12t 12t-ssi "${kind%%:*}" "${kind#*:}" --ssi
    hostile 60t 60t "${kind%%:*}" "${kind#*:}"
done

# The judge can fail: a wrong grade source, a counter that did not move,
# hostile frames against a record that has none of them.
must_fail() { # DESCRIPTION truck_judge arguments...
    mf_what=$1
    shift
    if "$tools/truck_judge" "$@" > "$out/must_fail.txt" 2>&1; then
        echo "foreign: truck_judge passed $mf_what"
        fail=1
    else
        echo "foreign: truck_judge fails $mf_what, as it should: $(grep "FAIL\|differs\|ends after" "$out/must_fail.txt" | head -n 1)"
    fi
}
must_fail "a record with SSI judged as one without" avail "$out/12t-ssi.rec" --grade-source 2
must_fail "a clean record judged as spoofed" hostile "$out/60t.rec" "$out/60t.rec" --bursts 10 \
    --expect conflicts
must_fail "a 60 t record judged against a 12 t one" hostile "$out/12t.rec" "$out/60t.rec" --bursts 10
must_fail "the printed and -L forms of two trucks' logs" same "$out/12t.txt" "$out/60t.log"
must_fail "the 12 t identification judged against the 60 t truth" identify "$out/12t-ident.rec" \
    --truth "$out/60t-ident.truth.csv" --from "$id_stop_s" --mass 12000
must_fail "the 12 t identification judged as a 60 t truck" identify "$out/12t-ident.rec" \
    --truth "$out/12t-ident.truth.csv" --from "$id_stop_s" --mass 60000
must_fail "a drive without the engine's LFE1 judged as identified" identify "$out/12t-ident-off.rec" \
    --truth "$out/12t-ident.truth.csv" --from "$id_stop_s" --mass 12000
must_fail "the engine's LFE1 said to stop before it does" identify "$out/12t-ident.rec" \
    --truth "$out/12t-ident.truth.csv" --from 100 --mass 12000

grep '^bench:' "$out/bench.txt" > "$out/bench.lines"
[ "$fail" -eq 0 ] && echo "foreign: every foreign-truck check holds"
exit "$fail"

#!/bin/sh
# Runs a command (default: make test) while the machine is loaded more
# heavily than it has cores, and says how long it took.
#
#   scripts/load_test.sh [--busy N] [--build-jobs J] [--limit-s S] [--log FILE] [-- COMMAND...]
#
# The load, all of it started here and bounded in time (each process runs
# under timeout(1) for at most S seconds, and is stopped by its id when the
# command ends):
#   - N CPU-bound processes (default: 2 per core, at least 4), busy loops of
#     the shell;
#   - a parallel build (make -j J, default 2) of the host tools, the
#     Cortex-M4 image and the sanitizer builds of the tools (make san) in a
#     scratch copy of this tree
#     (git ls-files, so nothing of build/), cleaned and built again until
#     the command ends.
# Two busy loops alone did not make the suite lose frames; the build adds
# what they lack: processes that start, read, write and exit all the time.
#
# Prints the load, the command's output (or only its tail with --log, the
# whole in FILE), then "load_test: COMMAND: exit E after T s under load
# (N busy, build -jJ; load average L at the end)". Exit status: the
# command's.
set -u

here=$(cd "$(dirname "$0")/.." && pwd)
cores=$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2)
busy=$((cores * 2))
[ "$busy" -ge 4 ] || busy=4
jobs=2
limit_s=5400
log=""
while [ $# -gt 0 ]; do
    case $1 in
    --busy) busy=$2; shift 2 ;;
    --build-jobs) jobs=$2; shift 2 ;;
    --limit-s) limit_s=$2; shift 2 ;;
    --log) log=$2; shift 2 ;;
    --) shift; break ;;
    *) echo "usage: $0 [--busy N] [--build-jobs J] [--limit-s S] [--log FILE] [-- COMMAND...]" >&2; exit 2 ;;
    esac
done
case "$busy$jobs$limit_s" in
*[!0-9]*) echo "load_test: --busy, --build-jobs and --limit-s take whole numbers" >&2; exit 2 ;;
esac
[ $# -gt 0 ] || set -- make -C "$here" test

scratch=$(mktemp -d "${TMPDIR:-/tmp}/pfe-load.XXXXXX")
pids=""
stop_load() {
    for p in $pids; do
        kill "$p" 2>/dev/null
    done
    for p in $pids; do
        wait "$p" 2>/dev/null
    done
    pids=""
    rm -rf "$scratch"
}
trap 'stop_load; exit 130' INT TERM

(cd "$here" && git ls-files -z | xargs -0 tar -cf - ) | tar -xf - -C "$scratch" ||
    { echo "load_test: cannot copy the tree to $scratch" >&2; exit 2; }

k=0
while [ "$k" -lt "$busy" ]; do
    timeout "$limit_s" sh -c 'while :; do :; done' &
    pids="$pids $!"
    k=$((k + 1))
done
# The build loop: its own process group, so that stopping it stops make too.
timeout "$limit_s" sh -c '
    cd "$1" || exit 1
    while :; do
        make -j"$2" BUILD=build-load tools firmware san >/dev/null 2>&1
        rm -rf build-load/host build-load/m4 build-load/host-san build-load/san
    done' sh "$scratch" "$jobs" &
pids="$pids $!"
sleep 2
echo "load_test: load: $busy busy loops and make -j$jobs in $scratch, on $cores cores," \
    "for at most $limit_s s; load average now $(cut -d' ' -f1 /proc/loadavg)"

t0=$(date +%s)
if [ -n "$log" ]; then
    "$@" >"$log" 2>&1
    rc=$?
    tail -n 30 "$log"
else
    "$@"
    rc=$?
fi
t1=$(date +%s)
la=$(cut -d' ' -f1 /proc/loadavg)
stop_load
echo "load_test: $*: exit $rc after $((t1 - t0)) s under load ($busy busy, build -j$jobs; load average $la at the end)"
exit "$rc"

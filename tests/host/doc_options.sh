#!/bin/sh
# The options the README and docs/ name for each host tool exist in its
# --help (tests/host/doc_options.py), and the check fails where it should:
# on an option no --help has, and on a --help that does not exit 0.
#
#   sh tests/host/doc_options.sh TOOLS_DIR
set -u
if [ $# -ne 1 ]; then
    echo "usage: $0 TOOLS_DIR" >&2
    exit 2
fi
tools=$1
check="python3 tests/host/doc_options.py"
work=$(mktemp -d "${TMPDIR:-/tmp}/doc_options.XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT
fails=0

echo "== the README and docs/ against the tools' --help"
if ! $check "$tools" README.md docs/*.md; then
    fails=$((fails + 1))
fi

# expect STATUS TEXT ARGS...: the check exits STATUS and prints TEXT.
expect() {
    want=$1 text=$2
    shift 2
    $check "$@" >"$work/out" 2>&1
    got=$?
    if [ "$got" -ne "$want" ] || ! grep -q -- "$text" "$work/out"; then
        echo "doc_options.sh: expected exit $want and '$text', got exit $got:"
        cat "$work/out"
        fails=$((fails + 1))
    else
        echo "refused as it should: $(grep -- "$text" "$work/out" | head -n 1)"
    fi
}

cat >"$work/README.md" <<'END'
| program | what it does | source |
|---|---|---|
| `pfe_replay` | replays a log | `sim_host/tools/pfe_replay.c` |
END
printf '# a page\n\nReplay with `pfe_replay -I drive.log --no-such-option 3`.\n' >"$work/doc.md"
expect 1 "pfe_replay --no-such-option: not in" "$tools" "$work/README.md" "$work/doc.md"

mkdir "$work/bin"
printf '#!/bin/sh\necho "usage: pfe_replay" >&2\nexit 2\n' >"$work/bin/pfe_replay"
chmod +x "$work/bin/pfe_replay"
expect 1 "pfe_replay --help: exit status 2, not 0" "$work/bin" "$work/README.md"

if [ "$fails" -ne 0 ]; then
    echo "doc_options.sh: $fails failed"
    exit 1
fi
echo "doc_options.sh: passed"

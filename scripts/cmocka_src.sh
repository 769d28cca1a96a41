#!/bin/sh
# Fetch CMocka's source package from Debian and unpack it under OUTDIR.
#
#   scripts/cmocka_src.sh OUTDIR
#
# Afterwards these paths are stable, whatever Debian's version of CMocka:
#   OUTDIR/cmocka/src/cmocka.c
#   OUTDIR/cmocka/include/cmocka.h
# (OUTDIR/cmocka is a symlink to the unpacked OUTDIR/pkg/cmocka-<version>.)
#
# The target build cross-compiles cmocka.c itself, because Debian ships CMocka
# only as a host library. Does nothing when the files are already there. When
# apt knows no source package (no deb-src entry), it writes one in its own
# file, mirroring the deb entries of /etc/apt/sources.list.d/debian.sources
# (or of /etc/apt/sources.list), and runs apt-get update. Needs root (or sudo)
# only in that case. OUTDIR belongs under build/ and is never committed.

set -eu

if [ $# -ne 1 ]; then
    echo "usage: $0 OUTDIR" >&2
    exit 2
fi
outdir=$1
link="$outdir/cmocka"

if [ -f "$link/src/cmocka.c" ] && [ -f "$link/include/cmocka.h" ]; then
    exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
    as_root=""
else
    as_root="sudo"
fi

src_list=/etc/apt/sources.list.d/cmocka-deb-src.sources

have_deb_src() {
    for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
        [ -f "$f" ] && grep -Eqs '^[[:space:]]*deb-src[[:space:]]' "$f" && return 0
    done
    for f in /etc/apt/sources.list.d/*.sources; do
        [ -f "$f" ] && grep -Eqs '^Types:.*deb-src' "$f" && return 0
    done
    return 1
}

add_deb_src() {
    tmp=$(mktemp)
    if [ -f /etc/apt/sources.list.d/debian.sources ]; then
        # Keep only stanzas whose Types is exactly "deb" and turn them into
        # deb-src stanzas; URIs, Suites, Components and Signed-By stay as they
        # are, so sources come from the same mirror and keyring as binaries.
        awk 'BEGIN { RS = ""; ORS = "\n\n" }
             /(^|\n)Types:[ \t]*deb[ \t]*(\n|$)/ {
                 sub(/(^|\n)Types:[ \t]*deb[ \t]*\n/, "\nTypes: deb-src\n");
                 sub(/^\n/, "");
                 print
             }' /etc/apt/sources.list.d/debian.sources >"$tmp"
    elif [ -f /etc/apt/sources.list ]; then
        sed -n 's/^[[:space:]]*deb[[:space:]]/deb-src /p' /etc/apt/sources.list >"$tmp"
        src_list=/etc/apt/sources.list.d/cmocka-deb-src.list
    fi
    if [ ! -s "$tmp" ]; then
        rm -f "$tmp"
        echo "cmocka_src.sh: no deb entries found to mirror as deb-src" >&2
        exit 1
    fi
    $as_root install -m 0644 "$tmp" "$src_list"
    rm -f "$tmp"
    echo "cmocka_src.sh: added $src_list" >&2
}

if ! apt-cache showsrc cmocka 2>/dev/null | grep -q '^Package: cmocka'; then
    have_deb_src || add_deb_src
    $as_root apt-get -o DPkg::Lock::Timeout=900 -qq update
fi

mkdir -p "$outdir/pkg"
pkgdir=$(cd "$outdir/pkg" && pwd)
# A previous run may have stopped half-way: start from an empty folder.
rm -rf "${pkgdir:?}"/* "$link"
# apt-get source downloads the .dsc and tarballs and unpacks them with
# dpkg-source into the current folder.
(cd "$pkgdir" && apt-get -qq source cmocka >/dev/null 2>"$pkgdir/apt-source.log") || {
    cat "$pkgdir/apt-source.log" >&2
    echo "cmocka_src.sh: apt-get source cmocka failed" >&2
    exit 1
}

srcdir=""
for d in "$pkgdir"/cmocka-*; do
    [ -d "$d" ] && [ -f "$d/src/cmocka.c" ] && srcdir=$d
done
if [ -z "$srcdir" ]; then
    echo "cmocka_src.sh: no unpacked cmocka-*/src/cmocka.c under $pkgdir" >&2
    exit 1
fi
ln -s "pkg/$(basename "$srcdir")" "$link"
[ -f "$link/src/cmocka.c" ] && [ -f "$link/include/cmocka.h" ]

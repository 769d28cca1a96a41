#!/bin/sh
# Run a command on a machine that has a virtual CAN interface vcan0, and return
# its exit code and output.
#
#   scripts/vcan_vm.sh [--timeout S] [--payload DIR]... [--time] [--vm|--native]
#                      -- COMMAND [ARG...]
#
# Native: when this machine can have a vcan0 (one exists, or
# `ip link add dev vcan0 type vcan` works: a Linux laptop, as root), COMMAND
# runs here with vcan0 (and vcan1 where it can be created) up. Interfaces this
# script created are deleted afterwards; others are left as they were.
#
# VM: otherwise (a kernel without CAN, as on the build machines) COMMAND runs
# inside Debian's own kernel under `qemu-system-x86_64 -accel tcg` (never KVM:
# a KVM boot hung on the build machines), on an initramfs with busybox-static,
# the CAN modules (can, can-raw, can-dev, vcan; vxcan, can-j1939 and slcan too
# when the kernel has them) and can-utils (candump, cansend, canplayer, cangen and a few
# more, with the shared libraries ldd lists). The VM brings up vcan0 and vcan1,
# changes to this working directory and runs COMMAND there with stdin from
# /dev/null. COMMAND's stdout and stderr, merged in the order it wrote them
# (as with 2>&1), reach this script's stdout through a serial port of their
# own, as they come; the kernel's console (and the exit code marker) goes to
# another, kept in the cache as last-console.log. (Two ports for stdout and
# stderr would cut lines: each port drains on its own.)
#
# Only files under a --payload DIR exist in the VM, at the same absolute path
# (DIR is copied into the initramfs on each call), so COMMAND and its files
# must live there: programs linked with `gcc -static`, or shell scripts that
# use busybox and can-utils. Files the command writes are lost with the VM.
#
# The kernel comes from `apt-get download linux-image-<version>-amd64` (the
# version that linux-image-amd64 depends on, or $VCAN_VM_KERNEL), unpacked with
# dpkg-deb. The kernel, its CAN modules and the base initramfs are cached under
# $VCAN_VM_DIR (default build/vcan-vm of this repository), keyed by the kernel
# version; a later call only packs the payload, a second cpio archive appended
# to the cached one. Missing Debian packages are installed with scripts/deps.sh.
#
# Options:
#   --timeout S    limit for running COMMAND, VM boot included (default 300 s;
#                  the first download of the kernel comes on top)
#   --payload DIR  copy DIR into the VM at the same absolute path (repeatable;
#                  ignored natively)
#   --time         print on stderr how long the boot and the command took
#   --vm           use the VM even when this machine could run natively
#   --native       never use the VM: fail if vcan0 cannot be had here
#
# Environment:
#   VCAN_VM_DIR     cache folder (default <repository>/build/vcan-vm)
#   VCAN_VM_KERNEL  kernel version to use, e.g. 6.1.0-56-amd64
#   VCAN_VM_MEM_MB  VM memory (default 512; the initramfs lives in it)
#   QEMU_SYSTEM_X86 QEMU program (default qemu-system-x86_64)
#
# Exit status:
#   COMMAND's exit code (inside the VM too; 127: not found there)
#   124  the run did not finish in time (message on stderr)
#   125  usage or set-up error: missing packages, kernel download, no vcan0,
#        the VM failed to boot or lost the command's exit code (message and the
#        end of the VM's console on stderr)

set -eu

me=vcan_vm.sh
script_dir=$(cd "$(dirname "$0")" && pwd)
repo_root=$(cd "$script_dir/.." && pwd)

usage() {
    echo "usage: $0 [--timeout S] [--payload DIR]... [--time] [--vm|--native] -- COMMAND [ARG...]" >&2
    exit 125
}

die() {
    echo "$me: $*" >&2
    exit 125
}

# Milliseconds of a monotonic clock (the uptime): busybox's date has no %N.
now_ms() {
    awk '{ printf "%d\n", $1 * 1000 }' /proc/uptime 2>/dev/null || echo $(($(date +%s) * 1000))
}

# "1234" milliseconds -> "1.2"
fmt_s() {
    echo "$(($1 / 1000)).$((($1 % 1000) / 100))"
}

timeout_s=300
payloads=""
show_time=0
mode=auto
while [ $# -gt 0 ]; do
    case $1 in
    --timeout)
        [ $# -ge 2 ] || usage
        case $2 in '' | *[!0-9]*) die "--timeout wants whole seconds, not '$2'" ;; esac
        timeout_s=$2
        shift 2
        ;;
    --payload)
        [ $# -ge 2 ] || usage
        [ -d "$2" ] || die "--payload: no such folder: $2"
        payloads="$payloads$(cd "$2" && pwd)
"
        shift 2
        ;;
    --time)
        show_time=1
        shift
        ;;
    --vm)
        mode=vm
        shift
        ;;
    --native)
        mode=native
        shift
        ;;
    --)
        shift
        break
        ;;
    *) usage ;;
    esac
done
[ $# -ge 1 ] || usage

t_start=$(now_ms)

nl='
'

# What to undo on exit, however the script ends: interfaces it created,
# temporary folders (one per line), the processes that copy the VM's output.
created=""
tmp_dirs=""
cats=""
child=""
# shellcheck disable=SC2317 # reached through the EXIT trap
on_exit() {
    [ -z "$child" ] || kill "$child" 2>/dev/null || true
    for p in $cats; do kill "$p" 2>/dev/null || true; done
    for ifc in $created; do ip link delete dev "$ifc" 2>/dev/null || true; done
    printf '%s' "$tmp_dirs" | while IFS= read -r d; do rm -rf "$d"; done
}
trap on_exit EXIT
trap 'exit 130' INT TERM

# Runs "$@" under timeout in the background and waits for it, so that a
# Ctrl-C reaches this script at once (timeout puts its command in a process
# group of its own, out of the terminal's reach) and on_exit stops it: the
# TERM sent to timeout goes on to the command. Sets rc.
run_limited() {
    timeout -k 5 "$timeout_s" "$@" &
    child=$!
    rc=0
    wait "$child" || rc=$?
    child=""
}

# GNU timeout exits with 124 (137 after -k's SIGKILL); busybox's passes on
# the killed command's 143 or 137, so the clock decides those.
is_timeout() {
    case $1 in
    124) return 0 ;;
    137 | 143) [ $(($(now_ms) - $2)) -ge $((timeout_s * 1000)) ] ;;
    *) return 1 ;;
    esac
}

# ------------------------------------------------------------------ native

# vcan: iproute2 shows the link kind; busybox's ip cannot, so also accept
# what sysfs tells: type CAN (280) and no device behind it.
is_vcan() {
    ip -details link show dev "$1" 2>/dev/null | grep -q '^ *vcan ' && return 0
    [ "$(cat "/sys/class/net/$1/type" 2>/dev/null)" = 280 ] && [ ! -e "/sys/class/net/$1/device" ]
}

# Returns 0 with vcan0 up (creating what is missing), 1 when this machine
# cannot have a vcan0.
native_setup() {
    command -v ip >/dev/null 2>&1 || return 1
    if ! ip link show dev vcan0 >/dev/null 2>&1; then
        ip link add dev vcan0 type vcan 2>/dev/null || return 1
        created="vcan0"
        if ! ip link show dev vcan1 >/dev/null 2>&1 &&
            ip link add dev vcan1 type vcan 2>/dev/null; then
            created="$created vcan1"
        fi
    fi
    is_vcan vcan0 || { echo "$me: vcan0 exists but is not a vcan interface" >&2; return 1; }
    for ifc in vcan0 vcan1; do
        is_vcan "$ifc" || continue
        if ! ip link show dev "$ifc" | grep -q '[<,]UP[,>]'; then
            ip link set dev "$ifc" up || { echo "$me: cannot bring $ifc up" >&2; return 1; }
        fi
    done
    return 0
}

if [ "$mode" != vm ]; then
    if native_setup; then
        run_limited "$@" </dev/null
        if is_timeout "$rc" "$t_start"; then
            echo "$me: '$*' timed out after $timeout_s s" >&2
            rc=124
        fi
        if [ "$show_time" -eq 1 ]; then
            echo "$me: native run, total $(fmt_s $(($(now_ms) - t_start))) s" >&2
        fi
        exit "$rc"
    fi
    for ifc in $created; do ip link delete dev "$ifc" 2>/dev/null || true; done
    created=""
    [ "$mode" = native ] && die "no vcan0 here and 'ip link add dev vcan0 type vcan' fails (--native)"
fi

# ------------------------------------------------------------------ VM: packages

qemu=${QEMU_SYSTEM_X86:-qemu-system-x86_64}
# Programs the VM path needs, and the Debian package of each.
need="$qemu:qemu-system-x86 busybox:busybox-static cpio:cpio candump:can-utils
objcopy:binutils dpkg-deb:dpkg apt-get:apt gzip:gzip flock:util-linux"
missing=""
for pair in $need; do
    prog=${pair%%:*}
    pkg=${pair#*:}
    command -v "$prog" >/dev/null 2>&1 || missing="$missing $pkg"
done
# /bin/busybox must be the static build: it runs without a C library.
if [ "$(dpkg-query -W -f='${Status}' busybox-static 2>/dev/null || true)" != "install ok installed" ]; then
    case " $missing " in *" busybox-static "*) ;; *) missing="$missing busybox-static" ;; esac
fi
if [ -n "$missing" ]; then
    echo "$me: installing missing packages:$missing" >&2
    # shellcheck disable=SC2086 # one argument per package
    sh "$script_dir/deps.sh" $missing ||
        die "missing Debian packages:$missing (install them as root: scripts/deps.sh$missing)"
    for pair in $need; do
        command -v "${pair%%:*}" >/dev/null 2>&1 ||
            die "${pair%%:*} not found, although its package ${pair#*:} is installed"
    done
fi
busybox_bin=/bin/busybox
[ -x "$busybox_bin" ] || busybox_bin=$(command -v busybox)

# ------------------------------------------------------------------ VM: kernel and base initramfs

cache=${VCAN_VM_DIR:-$repo_root/build/vcan-vm}
mkdir -p "$cache"
cache=$(cd "$cache" && pwd)

# Everything in the cache is built under this lock: parallel calls wait for
# the first one instead of downloading the kernel twice.
exec 9>"$cache/.lock"
flock 9

kver=${VCAN_VM_KERNEL:-}
if [ -z "$kver" ]; then
    # A kernel already cached wins: no network, no rebuild.
    for d in "$cache"/kernel-*; do
        [ -f "$d/vmlinuz" ] && kver=${d##*/kernel-}
    done
fi
if [ -z "$kver" ]; then
    kver=$(apt-cache depends linux-image-amd64 2>/dev/null |
        sed -n 's/^ *Depends: linux-image-\([0-9][^ ]*-amd64\)$/\1/p' | head -n 1)
    if [ -z "$kver" ]; then
        kver=$(apt-cache pkgnames linux-image- 2>/dev/null |
            grep -E '^linux-image-[0-9][0-9.]*-[0-9]+-amd64$' |
            sed 's/^linux-image-//' | sort -V | tail -n 1)
    fi
    [ -n "$kver" ] || die "apt knows no linux-image-*-amd64 package (run apt-get update, or set VCAN_VM_KERNEL)"
fi
kdir="$cache/kernel-$kver"

# Modules the VM loads: the first four must exist; the others are loaded
# when the kernel has them (slcan: a CAN interface on a tty, what the guard
# test of the SocketCAN backend uses as a stand-in for a real bus).
want_modules="can can-raw can-dev vcan"
optional_modules="vxcan can-j1939 slcan"
modules_key="$want_modules|$optional_modules"

# .modinfo "depends=" of a module file: names separated by commas.
mod_depends() {
    objcopy -O binary --only-section=.modinfo "$1" /dev/stdout 2>/dev/null |
        tr '\0' '\n' | sed -n 's/^depends=//p' | tr ',' ' '
}

# Writes the uncompressed kernel inside bzImage $1 to $2, if it is an ELF with
# a PVH entry point (Xen note 18, XEN_ELFNOTE_PHYS32_ENTRY). QEMU boots such
# an ELF directly: under TCG that saves the 3 to 4 s the bzImage would spend
# decompressing itself.
extract_vmlinux() {
    for fmt in 'xz:\xFD7zXZ\x00' 'zstd:\x28\xB5\x2F\xFD' 'gzip:\x1F\x8B\x08'; do
        tool=${fmt%%:*}
        command -v "$tool" >/dev/null 2>&1 || continue
        for off in $(LC_ALL=C grep -obUaP "${fmt#*:}" "$1" 2>/dev/null | cut -d: -f1 | head -n 5); do
            # Data after the stream makes zstd and gzip complain: judge the output.
            tail -c +$((off + 1)) "$1" | "$tool" -dc 2>/dev/null >"$2.tmp" || true
            if readelf -n "$2.tmp" 2>/dev/null | grep -Eq 'Xen.*(0x00000012|PHYS32_ENTRY)'; then
                mv "$2.tmp" "$2"
                return 0
            fi
        done
    done
    rm -f "$2.tmp"
    return 1
}

fetch_kernel() {
    work="$cache/tmp-kernel.$$"
    rm -rf "$work" "$kdir"
    mkdir -p "$work"
    tmp_dirs="$tmp_dirs$work$nl"
    echo "$me: downloading linux-image-$kver (once; cached in $kdir)" >&2
    if ! (cd "$work" && apt-get -q -o APT::Sandbox::User=root download "linux-image-$kver" \
        >"$work/apt.log" 2>&1); then
        cat "$work/apt.log" >&2
        die "kernel download failed: apt-get download linux-image-$kver (network? apt-get update? VCAN_VM_KERNEL?)"
    fi
    deb=""
    for f in "$work"/linux-image-*.deb; do
        [ -f "$f" ] && deb=$f
    done
    [ -n "$deb" ] || die "apt-get download left no .deb in $work"
    dpkg-deb -x "$deb" "$work/root" || die "dpkg-deb -x $deb failed"
    moddir="$work/root/lib/modules/$kver"
    [ -d "$moddir" ] || moddir="$work/root/usr/lib/modules/$kver"
    [ -f "$work/root/boot/vmlinuz-$kver" ] || die "no boot/vmlinuz-$kver in $deb"
    [ -d "$moddir" ] || die "no lib/modules/$kver in $deb"
    mkdir -p "$work/out/modules"
    cp "$work/root/boot/vmlinuz-$kver" "$work/out/vmlinuz"
    cp "$work/root/boot/config-$kver" "$work/out/config" 2>/dev/null || true
    extract_vmlinux "$work/out/vmlinuz" "$work/out/vmlinux" ||
        echo "$me: no PVH kernel inside vmlinuz-$kver: booting the bzImage (slower)" >&2

    # Copy each wanted module and what it depends on, uncompressed; record a
    # load order in which every module follows its dependencies.
    todo="$want_modules"
    for m in $optional_modules; do
        if [ -n "$(find "$moddir" -name "$m.ko*" | head -n 1)" ]; then
            todo="$todo $m"
        fi
    done
    have=""
    while [ -n "$(printf '%s' "$todo" | tr -d ' ')" ]; do
        next=""
        for m in $todo; do
            m=$(echo "$m" | tr '_' '-')
            case " $have " in *" $m "*) continue ;; esac
            m_=$(echo "$m" | tr '-' '_')
            src=$(find "$moddir" \( -name "$m.ko*" -o -name "$m_.ko*" \) | head -n 1)
            [ -n "$src" ] || die "kernel $kver has no module $m"
            dst="$work/out/modules/$m.ko"
            case $src in
            *.ko) cp "$src" "$dst" ;;
            *.ko.xz) xz -dc "$src" >"$dst" ;;
            *.ko.zst) zstd -qdc "$src" >"$dst" ;;
            *.ko.gz) gzip -dc "$src" >"$dst" ;;
            *) die "unknown module format: $src" ;;
            esac
            have="$have $m"
            next="$next $(mod_depends "$dst")"
        done
        todo=$next
    done
    order=""
    left="$have"
    while [ -n "$(printf '%s' "$left" | tr -d ' ')" ]; do
        progress=0
        next=""
        for m in $left; do
            ready=1
            for d in $(mod_depends "$work/out/modules/$m.ko"); do
                d=$(echo "$d" | tr '_' '-')
                case " $order " in *" $d "*) ;; *) ready=0 ;; esac
            done
            if [ "$ready" -eq 1 ]; then
                order="$order $m"
                progress=1
            else
                next="$next $m"
            fi
        done
        [ "$progress" -eq 1 ] || die "module dependency cycle among:$next"
        left=$next
    done
    echo "${order# }" >"$work/out/modules/order"
    printf '%s\n' "$modules_key" >"$work/out/modules/key"
    mv "$work/out" "$kdir"
    rm -rf "$work"
}

if [ ! -f "$kdir/vmlinuz" ] || [ ! -f "$kdir/modules/order" ] ||
    [ "$(cat "$kdir/modules/key" 2>/dev/null)" != "$modules_key" ]; then
    fetch_kernel
fi

# The init of the VM. Runs as PID 1: mounts (the root is the initramfs, in
# memory and writable: /tmp needs no tmpfs, and one would hide a payload
# there), loads the CAN modules, brings up
# vcan0 and vcan1, runs /vcan-vm/cmd (from the payload archive) with its
# output on ttyS1, prints the exit code marker on the console, and
# powers off. If poweroff fails, init returns: the kernel panics and, with
# panic=-1 and QEMU's -no-reboot, QEMU exits anyway (without the marker).
write_init() {
    cat >"$1" <<'EOF'
#!/bin/sh
export PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root TERM=dumb VCAN_VM=1
mount -t devtmpfs devtmpfs /dev 2>/dev/null
mkdir -p /dev/pts
mount -t devpts devpts /dev/pts
mount -t proc proc /proc
mount -t sysfs sysfs /sys
exec </dev/null >/dev/console 2>&1
fail() {
    echo "vcan-vm: $*"
    dmesg | tail -n 30
    echo "@@vcan-vm-exit 125@@"
    poweroff -f
    exit 1
}
for m in $(cat /lib/modules/can/order); do
    insmod "/lib/modules/can/$m.ko" || fail "insmod $m failed"
done
ip link set dev lo up
for i in vcan0 vcan1; do
    ip link add dev "$i" type vcan || fail "ip link add $i failed"
    ip link set dev "$i" up || fail "ip link set $i up failed"
done
# A raw port: the command's bytes reach the host unchanged (no \r added).
stty -F /dev/ttyS1 115200 raw -echo || fail "stty /dev/ttyS1 failed"
read -r up _ </proc/uptime
echo "@@vcan-vm-start $up@@"
sh /vcan-vm/cmd </dev/null >/dev/ttyS1 2>&1
rc=$?
read -r up _ </proc/uptime
# No kernel message may cut the marker line.
dmesg -n 1
echo "@@vcan-vm-end $up@@"
echo "@@vcan-vm-exit $rc@@"
poweroff -f
EOF
}

can_tools="candump cansend canplayer cangen cansequence canbusload log2asc asc2log"
bb_version=$("$busybox_bin" 2>&1 | head -n 1 || true)
cu_version=$(dpkg-query -W -f='${Version}' can-utils 2>/dev/null || true)
init_sum=$(cksum <"$0")
base_key="$kver|$bb_version|$cu_version|$can_tools|$init_sum"
base="$kdir/base.cpio.gz"

build_base() {
    stage="$cache/tmp-base.$$"
    rm -rf "$stage"
    tmp_dirs="$tmp_dirs$stage$nl"
    mkdir -p "$stage/bin" "$stage/sbin" "$stage/usr/bin" "$stage/usr/sbin" \
        "$stage/dev" "$stage/proc" "$stage/sys" "$stage/tmp" "$stage/run" \
        "$stage/root" "$stage/etc" "$stage/lib/modules/can" "$stage/vcan-vm"
    cp "$busybox_bin" "$stage/bin/busybox"
    for a in $("$busybox_bin" --list); do
        [ "$a" = busybox ] || ln -s busybox "$stage/bin/$a"
    done
    cp "$kdir"/modules/*.ko "$kdir/modules/order" "$stage/lib/modules/can/"
    for t in $can_tools; do
        p=$(command -v "$t") || die "can-utils has no $t"
        cp "$p" "$stage/usr/bin/$t"
        # Shared libraries and the loader at the paths ldd resolved.
        for lib in $(ldd "$p" 2>/dev/null | sed -n 's/.*=> \(\/[^ ]*\) .*/\1/p; s/^[[:space:]]*\(\/[^ ]*\) (.*/\1/p'); do
            [ -f "$stage$lib" ] && continue
            mkdir -p "$stage$(dirname "$lib")"
            cp -L "$lib" "$stage$lib"
        done
    done
    write_init "$stage/init"
    chmod 0755 "$stage/init"
    echo "root:x:0:0:root:/root:/bin/sh" >"$stage/etc/passwd"
    (cd "$stage" && find . -print | sed 's|^\./||; /^\.$/d' |
        cpio -o -H newc -R 0:0 --quiet) | gzip -1 >"$base.tmp" ||
        die "packing the base initramfs failed"
    # The kernel reads an archive appended after a compressed one only from
    # a 4-byte aligned offset: pad with zeros (which it skips) to 512 bytes.
    size=$(wc -c <"$base.tmp")
    pad=$(((512 - size % 512) % 512))
    [ "$pad" -eq 0 ] || head -c "$pad" /dev/zero >>"$base.tmp"
    mv "$base.tmp" "$base"
    printf '%s\n' "$base_key" >"$kdir/base.key"
    rm -rf "$stage"
}

if [ ! -f "$base" ] || [ "$(cat "$kdir/base.key" 2>/dev/null)" != "$base_key" ]; then
    build_base
fi
flock -u 9
exec 9>&-

# ------------------------------------------------------------------ VM: payload and run

run=$(mktemp -d "$cache/run.XXXXXX")
tmp_dirs="$tmp_dirs$run$nl"

# sh single quoting: a'b -> 'a'\''b'
quote() {
    printf "'%s'" "$(printf '%s' "$1" | sed "s/'/'\\\\''/g")"
}

cwd=$(pwd)
mkdir -p "$run/stage/vcan-vm"
{
    echo "cd $(quote "$cwd") || exit 125"
    printf 'exec'
    for a in "$@"; do printf ' %s' "$(quote "$a")"; done
    echo
} >"$run/stage/vcan-vm/cmd"

# Parent folders first: the kernel's cpio unpacker does not create them.
parents() {
    p=$1
    list=""
    while [ "$p" != / ] && [ -n "$p" ]; do
        list="$p
$list"
        p=$(dirname "$p")
    done
    printf '%s' "$list"
}

{
    parents "$cwd"
    printf '%s' "$payloads" | while IFS= read -r d; do
        parents "$(dirname "$d")"
        find "$d" -print
    done
} | sed 's|^/||' >"$run/list"
(cd / && cpio -o -H newc -R 0:0 --quiet <"$run/list") >"$run/payload.cpio" ||
    die "packing the payload failed"
(cd "$run/stage" && echo vcan-vm/cmd | cpio -o -H newc -R 0:0 --quiet) >"$run/cmd.cpio"
cat "$base" "$run/payload.cpio" "$run/cmd.cpio" >"$run/initrd"

# One boot of the VM running the command: sets rc, t_boot and t_end and
# leaves the console in $run/console.
boot_vm() {
    rm -f "$run/out" "$run/console"
    # The command's output: QEMU writes into a FIFO that cat drains, which works
    # whatever this script's stdout is (terminal, pipe, file, socket).
    mkfifo "$run/out"
    cat "$run/out" &
    cats="$!"

    kernel="$kdir/vmlinuz"
    [ -f "$kdir/vmlinux" ] && kernel="$kdir/vmlinux"

    t_boot=$(now_ms)
    run_limited "$qemu" -accel tcg -machine pc -m "${VCAN_VM_MEM_MB:-512}" -smp 1 \
        -nodefaults -no-user-config -display none -monitor none -no-reboot \
        -kernel "$kernel" -initrd "$run/initrd" \
        -append "console=ttyS0,115200 quiet loglevel=4 panic=-1 rdinit=/init mitigations=off no_timer_check" \
        -serial "file:$run/console" -serial "file:$run/out" \
        </dev/null >"$run/qemu.log" 2>&1
    t_end=$(now_ms)
    # A QEMU that failed early never opened the FIFO, and cat would wait for a
    # writer for ever: open it as a writer (read-write never blocks) and close
    # it, which ends a waiting cat and leaves a finished one alone.
    exec 8<>"$run/out"
    exec 8>&-
    for p in $cats; do wait "$p" 2>/dev/null || true; done
    cats=""
    [ -f "$run/console" ] || : >"$run/console"
    cp "$run/console" "$cache/last-console.log"
}

boot_vm
# A kernel that panics in its first second, before the command started (on
# a heavily loaded host TCG's timer can fail the kernel's IO-APIC timer
# check: "IO-APIC + timer doesn't work"), is a failed boot, not a failed
# test: booted once more, and said so.
if [ "$rc" -eq 0 ] && ! grep -q '@@vcan-vm-start' "$run/console" && grep -q 'Kernel panic' "$run/console"; then
    echo "$me: the VM's kernel panicked while booting ($(tr -d '\r' <"$run/console" | grep -m 1 'Kernel panic' | sed 's/^\[[^]]*\] *//')); booting again" >&2
    boot_vm
fi

console_tail() {
    echo "$me: end of the VM's console ($cache/last-console.log):" >&2
    tr -d '\r' <"$run/console" | tail -n 25 | sed 's/^/  | /' >&2
    [ -s "$run/qemu.log" ] && sed 's/^/  qemu: /' "$run/qemu.log" >&2
    return 0
}

if is_timeout "$rc" "$t_boot"; then
    echo "$me: '$*' timed out after $timeout_s s in the VM (kernel $kver)" >&2
    console_tail
    exit 124
fi

marker() {
    tr -d '\r' <"$run/console" | sed -n "s/.*@@vcan-vm-$1 \\([0-9.]*\\)@@.*/\\1/p" | tail -n 1
}
cmd_rc=$(marker exit)
if [ "$rc" -ne 0 ] || [ -z "$cmd_rc" ]; then
    echo "$me: the VM ended without the command's exit code (QEMU exit $rc)" >&2
    console_tail
    exit 125
fi

if [ "$show_time" -eq 1 ]; then
    up_start=$(marker start)
    up_end=$(marker end)
    echo "$me: kernel $kver: command started ${up_start:-?} s after boot, ran" \
        "$(awk -v a="${up_start:-0}" -v b="${up_end:-0}" 'BEGIN { printf "%.1f", b - a }') s;" \
        "VM run $(fmt_s $((t_end - t_boot))) s, total $(fmt_s $((t_end - t_start))) s" >&2
fi
exit "$cmd_rc"

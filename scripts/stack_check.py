#!/usr/bin/env python3
"""Worst-case stack of a Cortex-M4 image, against its linker script's stack.

    scripts/stack_check.py --elf IMAGE.elf --ci FILE.ci... [--su FILE.su...]
                           --indirect scripts/stack_indirect.txt
                           [--measured BYTES] [--name NAME]

Inputs: the image, and the call graph and stack usage GCC wrote for exactly
that image (-fcallgraph-info=su -fstack-usage at its link-time code
generation: with -flto the .ci/.su files come from the link; mk/hardening.mk
checks that the link that wrote them produced the same bytes as the image).

Frames: each function's stack usage from the .ci file (the .su figures,
checked against the .su files when given), and, for functions GCC did not
compile here (libc, libgcc), from the image's disassembly: the sum of every
stack-pointer decrement in the function (push, stmdb sp!, sub sp, #n),
which bounds the frame from above. A function that moves sp by a register
(alloca, variable-length arrays) or whose .su usage is "dynamic" without
"bounded" is refused.

Call graph: the .ci edges united with the direct branches of the
disassembly (bl, and b/b.w to the start of another function: tail calls and
inline assembly such as hal_mps2_default_handler's branch to
report_exception). Indirect calls: every one in the .ci must match an entry
of the --indirect file, which lists its possible targets; every register
branch (blx rN, bx rN other than lr) in the disassembly must belong to a
function with such a call (a switch's table branch, adr rX then ldr pc,
[rX, rY, lsl #2] with the table right after it and every entry inside the
same function, is a jump within the function, not a call); every function
whose address is stored in the image (outside the vector table) must be
listed as a target. A target "!FUNC" says the call's pointer is set only by
FUNC: the image must not link FUNC (then the pointer stays NULL and the call
is never made). Anything else,
and any cycle (recursion), is refused: the bound would not be one.

Exceptions: the vector table is read from the image. The thread starts at
Reset_Handler. An exception stacks 32 bytes (basic frame: the images use no
FPU, so no extended frame) plus 4 of alignment. The images never change
exception priorities, so the configurable ones (MemManage, BusFault,
UsageFault, SVC, DebugMon, PendSV, SysTick, interrupts) all run at reset
priority 0 and cannot preempt each other; HardFault (-1) can preempt them,
NMI (-2) can preempt HardFault. Worst case: the deepest thread path, plus for
each of the three levels one exception frame and its deepest handler path.

Prints the worst path of each level, the total, the stack size (the image's
__stack_size symbol, linker/mps2_an386.ld) and the margin; --measured (a
high-water mark of the same image) is checked to be at most the bound.
Exit status: 0 fits, 1 does not fit or the analysis is refused, 2 usage or
tool error.
"""

import argparse
import os
import re
import subprocess
import sys

EXC_FRAME = 32 + 4  # basic exception frame + alignment padding (CCR.STKALIGN)

CROSS = os.environ.get("M4_CROSS", "arm-none-eabi-")
OBJDUMP = os.environ.get("M4_OBJDUMP", CROSS + "objdump")
NM = os.environ.get("M4_NM", CROSS + "nm")
READELF = os.environ.get("M4_READELF", CROSS + "readelf")
OBJCOPY = os.environ.get("M4_OBJCOPY", CROSS + "objcopy")


class Refused(Exception):
    pass


def die(msg, code=2):
    print("stack: %s" % msg, file=sys.stderr)
    sys.exit(code)


def run(cmd):
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           universal_newlines=True)
    except OSError as e:
        die("cannot run %s: %s" % (cmd[0], e.strerror))
    if p.returncode != 0:
        die("%s failed: %s" % (" ".join(cmd), p.stderr.strip()))
    return p.stdout


# ------------------------------------------------------------------ the image

def read_symbols(elf, preferred):
    """Functions of the image as canonical name -> (addr, size), every name
    (aliases included) -> canonical name, names given to two different
    functions, and every symbol's value. Aliases (one address, several
    names: the weak exception handlers) take the name GCC's call graph
    uses, else the global one. A function symbol of size 0 (libgcc's
    assembly) extends to the next function."""
    syms = []
    values = {}
    for line in run([READELF, "-sW", elf]).split("\n"):
        f = line.split()
        if len(f) < 8 or not f[0].endswith(":"):
            continue
        try:
            value = int(f[1], 16)
            size = int(f[2], 0)
        except ValueError:
            continue
        values[f[7]] = value
        if f[3] == "FUNC":
            syms.append((f[7], value & ~1, size, f[4]))
    starts = sorted({a for _, a, _, _ in syms})
    by_addr = {}
    for name, addr, size, bind in syms:
        if size == 0:
            later = [a for a in starts if a > addr]
            size = (later[0] - addr) if later else 0
        by_addr.setdefault(addr, []).append((name, size, bind))
    funcs = {}
    alias = {}
    seen = {}
    dup = set()
    for addr, names in by_addr.items():
        names.sort(key=lambda x: (x[0] not in preferred, x[2] != "GLOBAL", x[0]))
        canon = names[0][0]
        funcs[canon] = (addr, max(sz for _, sz, _ in names))
        for name, _, _ in names:
            if name in seen and seen[name] != addr:
                dup.add(name)
            seen[name] = addr
            alias[name] = canon
    return funcs, alias, dup, values


def section_bytes(elf, name):
    out = os.path.join(os.environ.get("TMPDIR", "/tmp"), "stack_check.%d.bin" % os.getpid())
    try:
        run([OBJCOPY, "-O", "binary", "--only-section=" + name, elf, out])
        with open(out, "rb") as f:
            return f.read()
    finally:
        if os.path.exists(out):
            os.remove(out)


def words(data):
    return [int.from_bytes(data[i:i + 4], "little") for i in range(0, len(data) - 3, 4)]


def section_addr(elf, name):
    """The load address of a section (readelf -S), None if absent."""
    for line in run([READELF, "-S", "-W", elf]).splitlines():
        m = re.search(r"\]\s+(\S+)\s+\S+\s+([0-9a-f]{8})\s", line)
        if m and m.group(1) == name:
            return int(m.group(2), 16)
    return None


def string_ranges(elf):
    """Address ranges of the image's string literals: the .rodata.str*
    input sections of its map file (NAME.map beside NAME.elf), which hold
    NUL-terminated strings only. A word there is text, never an address
    (")\n" and its padding read as 0x00000a29). No map file: none."""
    path = elf[:-4] + ".map" if elf.endswith(".elf") else elf + ".map"
    if not os.path.exists(path):
        return []
    out = []
    pending = False
    with open(path, errors="replace") as f:
        for line in f:
            m = re.match(r"^ (\.rodata\.str\S*)(.*)$", line)
            rest = None
            if m:
                rest = m.group(2)
                pending = rest.strip() == ""
            elif pending:
                rest = line
                pending = False
            if rest:
                a = re.match(r"^\s+0x([0-9a-f]+)\s+0x([0-9a-f]+)", rest)
                if a and int(a.group(2), 16) > 0:
                    out.append((int(a.group(1), 16), int(a.group(1), 16) + int(a.group(2), 16)))
    return out


def data_words(elf, name):
    """The words of a data section, but for those inside string literals."""
    data = section_bytes(elf, name)
    base = section_addr(elf, name)
    strings = string_ranges(elf) if base is not None else []
    out = []
    for i in range(0, len(data) - 3, 4):
        a = (base or 0) + i
        if any(lo <= a and a + 4 <= hi for lo, hi in strings):
            continue
        out.append(int.from_bytes(data[i:i + 4], "little"))
    return out


INSN = re.compile(r"^\s*([0-9a-f]+):\s+(\S+)\s*(.*)$")
TARGET = re.compile(r"^([0-9a-f]+)\s+<([^>+]+)(\+0x[0-9a-f]+)?>")
REGLIST = re.compile(r"\{([^}]*)\}")


def reg_count(operands):
    """Registers in a list such as {r4, r5, r6, r7, sl, lr} or {r4-r7, lr}."""
    m = REGLIST.search(operands)
    if not m:
        return 0
    n = 0
    for part in m.group(1).split(","):
        part = part.strip()
        r = re.match(r"[a-z]+(\d+)-[a-z]+(\d+)$", part)
        if r:
            n += int(r.group(2)) - int(r.group(1)) + 1
        elif part:
            n += 1
    return n


COND = "(eq|ne|cs|cc|hs|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?"
BRANCH = re.compile(r"^(b|bl|blx)" + COND + "$")
REG_BRANCH = re.compile(r"^(bx|blx)" + COND + "$")


def disassemble(elf, funcs):
    """Per function: SP decrement sum, direct callees, register branches,
    and the addresses stored in literal pools."""
    by_addr = {a: n for n, (a, s) in funcs.items()}
    ranges = sorted((a, a + s, n) for n, (a, s) in funcs.items())
    info = {n: {"frame": 0, "calls": set(), "regbranch": [], "dynamic": None} for n in funcs}
    pool_words = []
    cur = None
    ri = 0
    prev = None      # (function, address, op, operands) of the last instruction
    table = None     # the switch table being read: function, its bounds, entries
    for line in run([OBJDUMP, "-d", "--no-show-raw-insn", elf]).split("\n"):
        m = INSN.match(line)
        if not m:
            continue
        addr = int(m.group(1), 16)
        op, rest = m.group(2), m.group(3).split("@")[0].strip()
        # The function containing addr.
        while ri < len(ranges) and ranges[ri][1] <= addr:
            ri += 1
        cur = ranges[ri][2] if (ri < len(ranges) and ranges[ri][0] <= addr) else None
        if op == ".word":
            try:
                w = int(rest.split()[0], 16)
            except (ValueError, IndexError):
                continue
            pool_words.append(w)
            if table is not None and cur == table["func"]:
                # A case of the switch: a Thumb address inside the function.
                if (w & 1) and table["lo"] <= (w & ~1) < table["hi"]:
                    table["entries"] += 1
                else:
                    info[cur]["regbranch"].append("switch table entry 0x%x at 0x%x leaves %s"
                                                  % (w, addr, cur))
            continue
        if table is not None and op.split(".")[0] == "nop" and table["entries"] == 0:
            continue  # the padding that aligns the table after a 2-byte-aligned ldr.w
        if table is not None:
            if table["entries"] == 0:
                info[table["func"]]["regbranch"].append("switch table without entries at 0x%x"
                                                        % table["at"])
            table = None
        if cur is None:
            prev = None
            continue
        fi = info[cur]
        base = op.split(".")[0]
        pre_dec = re.search(r"\[sp,\s*#-(\d+)\]!", rest)
        if base == "push":
            fi["frame"] += 4 * reg_count(rest)
        elif base == "vpush":
            fi["frame"] += (8 if "d" in rest else 4) * reg_count(rest)
        elif base in ("stmdb", "stmfd") and rest.startswith("sp!"):
            fi["frame"] += 4 * reg_count(rest)
        elif pre_dec:
            fi["frame"] += int(pre_dec.group(1))
        elif base == "msr" and re.match(r"(msp|psp)\b", rest, re.I):
            fi["dynamic"] = "%s %s at 0x%x" % (op, rest, addr)
        elif re.match(r"sp,", rest) or re.match(r"sp!,", rest):
            imm = re.match(r"sp,\s*(sp,\s*)?#(\d+)$", rest)
            if base in ("sub", "subw") and imm:
                fi["frame"] += int(imm.group(2))
            elif base in ("add", "addw") and imm:
                pass  # releases what the decrements took
            elif base in ("ldmia", "ldmfd", "ldm") or (base == "mov" and rest == "sp, r7"):
                pass  # pops; the frame pointer restored
            elif base in ("str", "strd", "strh", "strb", "cmp", "cmn", "tst", "teq"):
                pass  # sp read, not written
            else:
                fi["dynamic"] = "%s %s at 0x%x" % (op, rest, addr)
        if BRANCH.match(base) and not re.match(r"(r\d+|ip|lr)$", rest):
            t = TARGET.match(rest)
            if t:
                taddr = int(t.group(1), 16)
                tname = by_addr.get(taddr)
                if tname is not None and tname != cur:
                    fi["calls"].add(tname)
        elif REG_BRANCH.match(base) and re.match(r"(r\d+|ip)$", rest):
            fi["regbranch"].append("%s %s at 0x%x" % (op, rest, addr))
        elif base == "mov" and re.match(r"pc,", rest):
            fi["regbranch"].append("%s %s at 0x%x" % (op, rest, addr))
        elif base == "ldr" and re.match(r"pc,", rest) and not re.match(r"pc,\s*\[sp\]", rest):
            # GCC's switch: adr rX, TABLE; ldr.w pc, [rX, rY, lsl #2]; TABLE
            # right after (or after a nop aligning it), every entry an address in this function: a jump
            # within it, not a call.
            jt = re.match(r"pc,\s*\[(r\d+),\s*r\d+,\s*lsl\s*#2\]$", rest)
            adr = None
            if jt and prev is not None and prev[0] == cur and prev[2].split(".")[0] == "add":
                adr = re.match(r"(r\d+),\s*pc,\s*#(\d+)$", prev[3])
            # the table follows the ldr.w, or the nop that aligns it to 4
            at = ((prev[1] + 4) & ~3) + int(adr.group(2)) if adr else -1
            if (adr and adr.group(1) == jt.group(1) and
                    (at == addr + 4 or (at == addr + 6 and at % 4 == 0))):
                lo, size = funcs[cur]
                table = {"func": cur, "lo": lo, "hi": lo + size, "entries": 0, "at": addr}
            else:
                fi["regbranch"].append("%s %s at 0x%x" % (op, rest, addr))
        prev = (cur, addr, op, rest)
    return info, pool_words


# ------------------------------------------------------------------ GCC's files

NODE = re.compile(r'^node: \{ title: "([^"]+)" label: "([^"]*)"')
EDGE = re.compile(r'^edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"(?: label: "([^"]*)")?')


def short(title):
    return title.rsplit(":", 1)[1] if ".o:" in title else title


def read_ci(paths):
    nodes = {}
    edges = []
    for p in paths:
        try:
            text = open(p, encoding="utf-8").read()
        except OSError as e:
            die("cannot read %s: %s" % (p, e.strerror))
        for line in text.split("\n"):
            m = NODE.match(line)
            if m:
                label = m.group(2).split("\\n")
                usage = None
                for part in label[1:]:
                    u = re.match(r"(\d+) bytes \(([^)]*)\)", part)
                    if u:
                        usage = (int(u.group(1)), u.group(2))
                loc = label[1] if len(label) > 1 and ":" in label[1] else None
                title = short(m.group(1))
                # An LTO partition that only calls a function lists it too,
                # without its usage: the defining partition's node wins.
                if usage is not None or title not in nodes:
                    nodes[title] = {"usage": usage, "loc": loc}
                continue
            m = EDGE.match(line)
            if m:
                edges.append((short(m.group(1)), short(m.group(2)), m.group(3)))
    return nodes, edges


def check_su(paths, nodes):
    """Every .su line has a .ci node at the same place with the same usage."""
    by_loc = {}
    for n, d in nodes.items():
        if d["loc"] and d["usage"]:
            by_loc.setdefault(d["loc"], []).append(d["usage"])
    count = 0
    for p in paths:
        for line in open(p, encoding="utf-8").read().split("\n"):
            f = line.split("\t")
            if len(f) != 3:
                continue
            loc = f[0].rsplit(":", 1)[0]
            usage = (int(f[1]), f[2])
            if usage not in by_loc.get(loc, []):
                die("%s: %s: no call-graph node with this usage" % (p, line))
            count += 1
    return count


def read_indirect(path):
    """Entries: FILE  TEXT  TARGET... ; TARGET @init_array: the image's
    .preinit_array and .init_array entries."""
    entries = []
    for n, raw in enumerate(open(path, encoding="utf-8").read().split("\n"), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        f = line.split()
        if len(f) < 3:
            die("%s:%d: expected FILE CALL-TEXT TARGET..." % (path, n))
        entries.append({"file": f[0], "text": f[1], "targets": f[2:], "where": "%s:%d" % (path, n)})
    return entries


# ------------------------------------------------------------------ analysis

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--elf", required=True)
    ap.add_argument("--ci", nargs="+", required=True)
    ap.add_argument("--su", nargs="*", default=[])
    ap.add_argument("--indirect", required=True)
    ap.add_argument("--measured", type=int)
    ap.add_argument("--name")
    ap.add_argument("--verbose", action="store_true", help="every function's frame and callees")
    args = ap.parse_args()
    name = args.name or os.path.basename(args.elf)

    nodes, ci_edges = read_ci(args.ci)
    funcs, alias, dup, values = read_symbols(args.elf, set(nodes))
    nodes = {alias.get(n, n): d for n, d in nodes.items()}
    ci_edges = [(alias.get(a, a), alias.get(b, b), l) for a, b, l in ci_edges]
    su_lines = check_su(args.su, nodes) if args.su else 0
    info, pool_words = disassemble(args.elf, funcs)
    indirect = read_indirect(args.indirect)
    refusals = []

    # Init arrays: the targets of startup.c's run_array().
    init_targets = set()
    for sec in (".preinit_array", ".init_array"):
        for w in words(section_bytes(args.elf, sec)):
            t = [n for n, (a, s) in funcs.items() if a == (w & ~1)]
            if not t:
                refusals.append("%s entry 0x%x is no function" % (sec, w))
            init_targets.update(t)

    # Call graph: .ci edges, indirect ones resolved, plus the disassembly's.
    calls = {n: set(info[n]["calls"]) for n in funcs}
    has_indirect = set()
    used_entries = set()
    src_cache = {}
    for src, dst, label in ci_edges:
        if src not in funcs:
            continue  # not in the image (removed by --gc-sections)
        if dst != "__indirect_call":
            if dst in funcs:
                calls[src].add(dst)
            continue
        has_indirect.add(src)
        if not label:
            refusals.append("indirect call in %s without a source location" % src)
            continue
        file, line = label.rsplit(":", 2)[0], int(label.rsplit(":", 2)[1])
        if file not in src_cache:
            try:
                src_cache[file] = open(file, encoding="utf-8").read().split("\n")
            except OSError:
                src_cache[file] = []
        text = src_cache[file][line - 1] if line <= len(src_cache[file]) else ""
        entry = next((e for i, e in enumerate(indirect)
                      if e["file"] == file and e["text"] in text), None)
        if entry is None:
            refusals.append("indirect call at %s (in %s: %s) has no entry in %s listing its targets"
                            % (label, src, text.strip(), args.indirect))
            continue
        used_entries.add(entry["where"])
        for t in entry["targets"]:
            if t == "@init_array":
                calls[src].update(init_targets)
            elif t.startswith("!"):
                # "!FUNC": the pointer is set only by FUNC; an image without
                # FUNC leaves it NULL and never makes this call.
                if t[1:] in funcs:
                    refusals.append("%s: %s sets the pointer of %s, and the image links it: list "
                                    "the targets instead" % (entry["where"], t[1:], label))
            elif t in funcs:
                calls[src].add(t)
            else:
                refusals.append("%s: target %s of %s is not in the image" % (entry["where"], t, label))

    for n in funcs:
        if info[n]["regbranch"] and n not in has_indirect and n not in nodes:
            refusals.append("%s (not compiled here) branches through a register: %s"
                            % (n, "; ".join(info[n]["regbranch"])))
        elif info[n]["regbranch"] and n not in has_indirect:
            refusals.append("%s branches through a register the call graph does not know: %s"
                            % (n, "; ".join(info[n]["regbranch"])))

    # Every function whose address is stored must be a listed target.
    vectors = words(section_bytes(args.elf, ".isr_vector"))
    listed = set(init_targets)
    for e in indirect:
        listed.update(t for t in e["targets"] if (t != "@init_array") and not t.startswith("!"))
    stored = []
    for sec in (".rodata", ".data"):
        stored += data_words(args.elf, sec)
    by_thumb_addr = {a | 1: n for n, (a, s) in funcs.items()}
    for w in set(pool_words + stored):
        n = by_thumb_addr.get(w)
        if n is not None and n not in listed:
            refusals.append("the address of %s is stored in the image, but no indirect call lists it "
                            "as a target (%s)" % (n, args.indirect))

    # Frames.
    frame = {}
    frame_note = {}
    for n in funcs:
        d = info[n]
        if n in nodes and nodes[n]["usage"] is not None:
            size, qual = nodes[n]["usage"]
            if "dynamic" in qual and "bounded" not in qual:
                refusals.append("%s: stack usage %s (%d bytes) is not bounded" % (n, qual, size))
            frame[n] = max(size, d["frame"])
            frame_note[n] = "su" if size >= d["frame"] else "disassembly > su %d" % size
        else:
            if d["dynamic"]:
                refusals.append("%s moves sp by a register: %s" % (n, d["dynamic"]))
            frame[n] = d["frame"]
            frame_note[n] = "disassembly"

    # Roots from the vector table.
    def handler(k):
        if k >= len(vectors) or vectors[k] == 0:
            return None
        t = [n for n, (a, s) in funcs.items() if a == (vectors[k] & ~1)]
        if not t:
            refusals.append("vector %d (0x%x) is no function" % (k, vectors[k]))
            return None
        return t[0]

    levels = [("thread", [handler(1)]), ("priority 0 exceptions",
              [handler(k) for k in list(range(4, 16)) + list(range(16, len(vectors)))]),
              ("HardFault", [handler(3)]), ("NMI", [handler(2)])]

    for n in sorted(dup):
        if n in nodes:
            refusals.append("two functions named %s: the call graph cannot tell them apart" % n)

    # Deepest path from each function (DFS, refusing cycles).
    memo = {}
    state = {}

    def deepest(n, stack):
        if n in memo:
            return memo[n]
        if state.get(n) == "open":
            cyc = stack[stack.index(n):] + [n]
            raise Refused("recursion: " + " > ".join(cyc))
        state[n] = "open"
        best = (0, [])
        for c in sorted(calls.get(n, ())):
            d = deepest(c, stack + [n])
            if d[0] > best[0]:
                best = d
        state[n] = "done"
        memo[n] = (frame[n] + best[0], [n] + best[1])
        return memo[n]

    results = []
    try:
        for label, roots in levels:
            roots = sorted({r for r in roots if r is not None})
            if not roots:
                results.append((label, 0, []))
                continue
            best = max((deepest(r, []) for r in roots), key=lambda d: d[0])
            results.append((label, best[0], best[1]))
    except Refused as e:
        refusals.append(str(e))

    if "__stack_size" not in values:
        die("%s has no __stack_size symbol" % args.elf)
    stack_size = values["__stack_size"]

    if refusals:
        for r in refusals:
            print("stack: %s: refused: %s" % (name, r))
        print("stack: %s: FAILED (the worst case cannot be bounded)" % name)
        return 1

    if args.verbose:
        for n in sorted(memo):
            print("stack: %s:   %-40s %5d  %-24s deepest %5d  calls %s"
                  % (name, n, frame[n], frame_note[n], memo[n][0], " ".join(sorted(calls[n])) or "-"))
    total = 0
    for label, depth, path in results:
        extra = 0 if label == "thread" else (EXC_FRAME if path else 0)
        total += depth + extra
        if not path:
            print("stack: %s: %-22s none" % (name, label))
            continue
        steps = " > ".join("%s %d" % (p, frame[p]) for p in path)
        print("stack: %s: %-22s %5d bytes%s: %s" % (name, label, depth + extra,
              (" (%d of exception frame)" % extra) if extra else "", steps))
    margin = stack_size - total
    print("stack: %s: worst case %d bytes of %d (__stack_size): margin %d bytes "
          "(%d functions, %d .su lines checked)" % (name, total, stack_size, margin,
                                                   len(memo), su_lines))
    status = 0
    if args.measured is not None:
        if args.measured > total:
            print("stack: %s: measured high-water mark %d bytes exceeds the bound %d: the analysis "
                  "misses something" % (name, args.measured, total))
            status = 1
        else:
            print("stack: %s: measured high-water mark %d bytes <= bound %d (thread path alone %d)"
                  % (name, args.measured, total, results[0][1]))
    if margin < 0:
        print("stack: %s: FAILED: the worst case exceeds the stack by %d bytes" % (name, -margin))
        status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())

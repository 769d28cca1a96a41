#!/usr/bin/env python3
"""Fails when a CMocka test asserts a comparison that prints no values.

    scripts/check_asserts.py [--quiet] PATH...

PATH: C files, or folders searched for *.c and *.h. A finding is an
assert_true(X) or assert_false(X) whose condition X, once outer parentheses,
a leading '!' and top-level '&&' / '||' are taken apart, compares at its top
level (==, !=, <, <=, >, >=): on failure CMocka prints only the text of X,
never the numbers. Write it with assert_int_equal, assert_string_equal,
assert_memory_equal, assert_null ... or the ordering and tolerance macros of
tests/test_assert.h (ASSERT_LE, ASSERT_NEAR ...), which print both sides.
A condition that only holds or not (assert_true(frame_ok), assert_false(
hal_replay_next_us(...))) is fine: its text says everything.

Each finding prints as FILE:LINE: bare comparison: assert_true(...).
Exit status: 0 no finding, 1 findings, 2 usage or unreadable file.
"""

import os
import sys

ASSERTS = ("assert_true", "assert_false")
COMPARISONS = ("==", "!=", "<=", ">=", "<", ">")


def strip_code(text):
    """The text with comments, string and character literals blanked out
    (same length, newlines kept), so that offsets and lines still match."""
    out = list(text)
    i = 0
    n = len(text)
    while i < n:
        c = text[i]
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            for k in range(i, j):
                if out[k] != "\n":
                    out[k] = " "
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            for k in range(i, j):
                out[k] = " "
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            # Keep the quotes: "" still reads as an operand.
            for k in range(i + 1, j - 1):
                if out[k] != "\n":
                    out[k] = " "
            i = j
        else:
            i += 1
    return "".join(out)


def is_ident_char(c):
    return c.isalnum() or c == "_"


def find_calls(code, names=ASSERTS):
    """(name, start, open, close) of each call of one of NAMES in CODE
    (already stripped): start of the name, offsets of '(' and its ')'."""
    calls = []
    i = 0
    n = len(code)
    while i < n:
        if is_ident_char(code[i]) and (i == 0 or not is_ident_char(code[i - 1])):
            j = i
            while j < n and is_ident_char(code[j]):
                j += 1
            word = code[i:j]
            if word in names:
                k = j
                while k < n and code[k] in " \t\n":
                    k += 1
                if k < n and code[k] == "(":
                    close = matching_paren(code, k)
                    if close is not None:
                        calls.append((word, i, k, close))
                        i = close + 1
                        continue
            i = j
        else:
            i += 1
    return calls


def matching_paren(code, open_at):
    depth = 0
    for k in range(open_at, len(code)):
        if code[k] in "([{":
            depth += 1
        elif code[k] in ")]}":
            depth -= 1
            if depth == 0:
                return k
    return None


def top_level(expr):
    """Offsets of expr's characters at bracket depth 0."""
    depth = 0
    for k, c in enumerate(expr):
        if c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        elif depth == 0:
            yield k


def strip_parens(expr):
    e = expr.strip()
    while e.startswith("(") and matching_paren(e, 0) == len(e) - 1:
        e = e[1:-1].strip()
    return e


def split_top(expr, op):
    """expr cut at each top-level occurrence of '&&' or '||' (OP)."""
    parts = []
    last = 0
    skip = -1
    for k in top_level(expr):
        if k <= skip:
            continue
        if expr.startswith(op, k):
            parts.append(expr[last:k])
            last = k + 2
            skip = k + 1
    parts.append(expr[last:])
    return parts


def comparison_at(expr):
    """(offset, operator) of each top-level comparison in expr."""
    found = []
    ks = set(top_level(expr))
    k = 0
    n = len(expr)
    while k < n:
        if k not in ks:
            k += 1
            continue
        two = expr[k:k + 2]
        three = expr[k:k + 3]
        if three in ("<<=", ">>="):
            k += 3
        elif two in ("<<", ">>", "->", "&&", "||", "+=", "-=", "*=", "/=", "&=", "|=", "^=", "%="):
            k += 2
        elif two in ("==", "!=", "<=", ">="):
            found.append((k, two))
            k += 2
        elif expr[k] in "<>":
            found.append((k, expr[k]))
            k += 1
        else:
            k += 1
    return found


def conjuncts(cond, negated):
    """The parts of a condition that each must hold (assert_true) or each
    must fail (assert_false, NEGATED), as far as they can be taken apart."""
    e = strip_parens(cond)
    while e.startswith("!") and not e.startswith("!="):
        e = strip_parens(e[1:])
        negated = not negated
    op = "||" if negated else "&&"
    parts = split_top(e, op)
    if len(parts) == 1:
        # 'a && b' under assert_false, or 'a || b' under assert_true: the
        # comparisons inside still count.
        other = "&&" if negated else "||"
        alt = split_top(e, other)
        if len(alt) > 1:
            return [(strip_parens(p), negated) for p in alt]
        return [(e, negated)]
    out = []
    for p in parts:
        out.extend(conjuncts(p, negated))
    return out


def bare_comparison(cond):
    return any(comparison_at(part) for part, _ in conjuncts(cond, False))


def line_of(text, offset):
    return text.count("\n", 0, offset) + 1


def check_file(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    code = strip_code(text)
    findings = []
    for name, start, open_at, close in find_calls(code):
        if bare_comparison(code[open_at + 1:close]):
            shown = " ".join(text[start:close + 1].split())
            findings.append((line_of(text, start), shown))
    return findings


def sources(paths):
    for p in paths:
        if os.path.isdir(p):
            for root, dirs, files in os.walk(p):
                dirs.sort()
                for f in sorted(files):
                    if f.endswith((".c", ".h")):
                        yield os.path.join(root, f)
        else:
            yield p


def main(argv):
    args = argv[1:]
    quiet = False
    if args and args[0] == "--quiet":
        quiet = True
        args = args[1:]
    if not args or any(a.startswith("-") for a in args):
        print(__doc__.strip().split("\n\n")[0], file=sys.stderr)
        return 2
    total = 0
    files = 0
    for path in sources(args):
        try:
            found = check_file(path)
        except OSError as e:
            print(f"check_asserts: {path}: {e.strerror}", file=sys.stderr)
            return 2
        files += 1
        for line, shown in found:
            print(f"{path}:{line}: bare comparison: {shown}")
        total += len(found)
    if total:
        print(f"check_asserts: {total} assert(s) compare without printing the values"
              " (use assert_int_equal, ASSERT_LE ... of tests/test_assert.h)")
        return 1
    if not quiet:
        print(f"check_asserts: {files} file(s), no bare comparison in an assert")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

#!/usr/bin/env python3
"""MISRA C:2012 check of C sources with cppcheck's misra addon, enforced.

    scripts/misra_check.py --deviations FILE [--build-dir DIR] [--allow-unused]
                           [-I DIR]... SOURCE...

Runs cppcheck once over all SOURCES (one run, so that the rules that look
across translation units, 5.9, 8.6, 8.7, 2.5..., see all of them), then sorts
every finding into "covered by a deviation" or "not covered".

Debian's cppcheck ships the addon without the rule texts (they are MISRA's
copyright), so a finding names its rule by number only, e.g. misra-c2012-17.7.
The deviations file gives each deviated rule a short title of its own.

Deviations file: paragraphs separated by blank lines, '#' starts a comment.

    rule:   10.1                       rule number as the addon reports it
    title:  operand of an inappropriate essential type   (paraphrase)
    files:  firmware/pfe_fixed.h firmware/pfe_pi.*       shell globs
    match:  >> |<<                     optional: a Python regular expression
                                       searched in the source line reported
    reason: why the code is right as it is; may continue on
            indented lines.

A finding is covered by the first deviation whose rule, one of whose globs
and whose pattern (if any) match. Findings that are not MISRA findings
(cppcheck's own errors: syntax, preprocessor, addon failures) cannot be
deviated.

Exit status: 0 when every finding is covered and every deviation covers at
least one finding (an unused deviation is stale documentation; --allow-unused
turns that off, for runs over a subset of the sources); 1 when some finding is
not covered or some deviation unused; 2 on usage errors, a malformed
deviations file or when cppcheck fails.
"""

import argparse
import fnmatch
import os
import re
import subprocess
import sys

RULE_PREFIX = "misra-c2012-"
FIELD_SEP = "\x1f"  # unit separator: cannot occur in a file name or message


class Deviation:
    def __init__(self, path, line):
        self.where = "%s:%d" % (path, line)
        self.rule = None
        self.title = ""
        self.files = []
        self.match = None
        self.match_text = ""
        self.reason = ""
        self.hits = 0

    def covers(self, rule, path, text):
        if rule != self.rule:
            return False
        if not any(fnmatch.fnmatchcase(path, g) for g in self.files):
            return False
        return self.match is None or self.match.search(text) is not None


def fail_usage(msg):
    print("misra: %s" % msg, file=sys.stderr)
    sys.exit(2)


def read_deviations(path):
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().split("\n")
    except OSError as e:
        fail_usage("cannot read %s: %s" % (path, e.strerror))
    devs = []
    cur = None
    last_key = None

    def finish(d):
        if d is None:
            return
        for key in ("rule", "files", "reason"):
            if not getattr(d, key):
                fail_usage("%s: deviation has no '%s:'" % (d.where, key))
        if not re.fullmatch(r"[0-9]+\.[0-9]+", d.rule):
            fail_usage("%s: rule '%s' is not a rule number such as 17.7" % (d.where, d.rule))
        devs.append(d)

    for n, raw in enumerate(lines, 1):
        line = raw.rstrip()
        if line.lstrip().startswith("#"):
            continue
        if line == "":
            finish(cur)
            cur = None
            last_key = None
            continue
        if line[0] in " \t":
            if last_key != "reason":
                fail_usage("%s:%d: continuation line outside a reason" % (path, n))
            cur.reason += " " + line.strip()
            continue
        key, sep, value = line.partition(":")
        key = key.strip()
        value = value.strip()
        if sep == "" or key not in ("rule", "title", "files", "match", "reason"):
            fail_usage("%s:%d: expected 'rule:', 'title:', 'files:', 'match:' or 'reason:'" % (path, n))
        if cur is None:
            cur = Deviation(path, n)
        if key == "rule":
            cur.rule = value
        elif key == "title":
            cur.title = value
        elif key == "files":
            cur.files = value.split()
        elif key == "match":
            try:
                cur.match = re.compile(value)
            except re.error as e:
                fail_usage("%s:%d: bad pattern: %s" % (path, n, e))
            cur.match_text = value
        else:
            cur.reason = value
        last_key = key
    finish(cur)
    return devs


def source_line(cache, path, line):
    if path not in cache:
        try:
            with open(path, encoding="utf-8", errors="replace") as f:
                cache[path] = f.read().split("\n")
        except OSError:
            cache[path] = []
    text = cache[path]
    return text[line - 1] if 1 <= line <= len(text) else ""


def main():
    ap = argparse.ArgumentParser(description="MISRA C:2012 check (cppcheck misra addon)")
    ap.add_argument("--deviations", required=True)
    ap.add_argument("--build-dir", help="cppcheck's cache (faster reruns)")
    ap.add_argument("--allow-unused", action="store_true")
    ap.add_argument("--cppcheck", default=os.environ.get("CPPCHECK", "cppcheck"))
    ap.add_argument("-I", dest="includes", action="append", default=[])
    ap.add_argument("sources", nargs="+")
    args = ap.parse_args()

    devs = read_deviations(args.deviations)
    for s in args.sources:
        if not os.path.isfile(s):
            fail_usage("no such source: %s" % s)

    # The target: a 32-bit Arm core with unsigned plain char (the platform
    # file Debian ships), C11. No -D: every #if configuration is checked.
    cmd = [args.cppcheck, "--addon=misra", "--std=c11", "--platform=arm32-wchar_t4",
           "--quiet", "--error-exitcode=0",
           "--suppress=missingIncludeSystem",
           "--template={file}" + FIELD_SEP + "{line}" + FIELD_SEP + "{column}" + FIELD_SEP
           + "{severity}" + FIELD_SEP + "{id}" + FIELD_SEP + "{message}"]
    if args.build_dir:
        os.makedirs(args.build_dir, exist_ok=True)
        cmd.append("--cppcheck-build-dir=" + args.build_dir)
    cmd += ["-I" + d for d in args.includes]
    cmd += args.sources
    try:
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              universal_newlines=True)
    except OSError as e:
        fail_usage("cannot run %s: %s" % (args.cppcheck, e.strerror))
    if proc.returncode != 0:
        sys.stderr.write(proc.stdout + proc.stderr)
        fail_usage("cppcheck failed (exit %d)" % proc.returncode)

    findings = set()
    for raw in proc.stderr.split("\n"):
        if raw.strip() == "":
            continue
        parts = raw.split(FIELD_SEP)
        if len(parts) != 6:
            # Anything cppcheck prints outside the template (an addon's
            # traceback, a checker's complaint) is a finding nobody can deviate.
            findings.add(("", 0, 0, "cppcheck-output", raw.strip()))
            continue
        path, line, col, _sev, ident, msg = parts
        path = os.path.normpath(path)
        findings.add((path, int(line or 0), int(col or 0), ident, msg))

    cache = {}
    uncovered = []
    covered = 0
    for path, line, col, ident, msg in sorted(findings):
        text = source_line(cache, path, line) if path else ""
        rule = ident[len(RULE_PREFIX):] if ident.startswith(RULE_PREFIX) else None
        dev = None
        if rule is not None:
            dev = next((d for d in devs if d.covers(rule, path, text)), None)
        if dev is None:
            uncovered.append((path, line, col, ident, rule, msg, text))
        else:
            dev.hits += 1
            covered += 1

    for path, line, col, ident, rule, msg, text in uncovered:
        if rule is not None:
            print("%s:%d:%d: MISRA C:2012 rule %s (%s) not covered by a deviation\n    %s"
                  % (path, line, col, rule, ident, text.strip()))
        else:
            print("%s:%d:%d: cppcheck %s: %s" % (path or "-", line, col, ident, msg))

    unused = [d for d in devs if d.hits == 0]
    if not args.allow_unused:
        for d in unused:
            print("%s: deviation of rule %s (%s) covers no finding: remove it"
                  % (d.where, d.rule, " ".join(d.files)))

    rules = sorted({d.rule for d in devs}, key=lambda r: [int(x) for x in r.split(".")])
    print("misra: %d source files, %d findings: %d covered by deviations, %d not covered"
          % (len(args.sources), len(findings), covered, len(uncovered)))
    print("misra: %d deviations listed (%s), covering %d rules: %s"
          % (len(devs), args.deviations, len(rules), " ".join(rules)))
    for d in devs:
        print("misra:   %-6s %4d  %s%s" % (d.rule, d.hits, " ".join(d.files),
                                          ("  /" + d.match_text + "/") if d.match else ""))
    if uncovered or (unused and not args.allow_unused):
        print("misra: FAILED")
        return 1
    print("misra: passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The options the README and docs/ name for a host tool exist in its --help.

    doc_options.py TOOLS_DIR README.md [DOC.md ...] [--list-unattributed]

The tools are the programs of README.md's tool table (a table whose header
is "| program | what it does | source |"). For each: TOOLS_DIR/PROGRAM must
exist, `PROGRAM --help` must exit 0 and print its manual on standard output,
and, once sim_host/tools/ exists, the source the table names must exist
(before, a program neither built nor at its planned source is only named).

Then every option (-x, --name) written as code (`...` or a fenced block) in
the documents is given to the command named last before it in the same
paragraph, list item, table row or code line: one of the table's programs,
or a program that is not the project's (candump, make, openocd, scripts...;
their options are not checked). An option given to a program of the table
must appear in that program's --help. An option after no command at all is
not a tool's option (a formula, say) and is not checked; with
--list-unattributed they are listed.

Exit status 0 when everything holds, 1 when something does not (each
finding with its file and line), 2 on bad arguments.
"""
import os
import re
import subprocess
import sys

# Programs that are not the project's: their options are theirs.
EXTERNAL = {
    'candump', 'canplayer', 'cansend', 'cangen', 'canbusload', 'make', 'openocd',
    'st-flash', 'ip', 'gzip', 'gunzip', 'zcat', 'gnuplot', 'cppcheck', 'valgrind',
    'qemu-system-arm', 'qemu-system-x86_64', 'apt-get', 'apt', 'git', 'sh', 'timeout',
    'ulimit', 'gcc', 'clang', 'dpkg-deb', 'arm-none-eabi-gcc', 'arm-none-eabi-size',
    'python3', 'cmp', 'diff', 'awk', 'sed', 'grep', 'sort', 'insmod', 'modprobe',
    'slcand', 'slcan_attach', 'ldattach', 'cat', 'tee', 'time',
}
# Programs of the table whose name is also a plain word: only as code.
CODE_ONLY = {'sensitivity', 'selfcheck'}

OPTION = re.compile(r'(?<![\w/.=<>-])(--?[A-Za-z][A-Za-z0-9]*(?:-[A-Za-z0-9]+)*)')


def fail(msg):
    print('doc_options: ' + msg)


def tool_table(readme):
    rows = []
    lines = open(readme, encoding='utf-8').read().split('\n')
    in_table = False
    for n, line in enumerate(lines, 1):
        cells = [c.strip() for c in line.strip().strip('|').split('|')]
        if line.startswith('|') and cells[:3] == ['program', 'what it does', 'source']:
            in_table = True
            continue
        if in_table:
            if not line.startswith('|'):
                break
            if set(line.replace('|', '').strip()) <= set('-: '):
                continue
            prog = cells[0].strip('`')
            src = cells[2].strip('`') if len(cells) > 2 else ''
            rows.append((prog, src, n))
    return rows


def blocks(path):
    """(line, text, all_code) units: paragraphs, list items, table rows, code lines."""
    out = []
    cur, start = [], 0
    fenced = False
    for n, line in enumerate(open(path, encoding='utf-8').read().split('\n'), 1):
        if line.startswith('```'):
            if cur:
                out.append((start, '\n'.join(cur), False))
                cur = []
            fenced = not fenced
            continue
        if fenced:
            if out and out[-1][2] and out[-1][1].endswith('\\'):
                out[-1] = (out[-1][0], out[-1][1][:-1] + ' ' + line, True)  # continued
            else:
                out.append((n, line, True))
            continue
        new_unit = (line.strip() == '' or line.startswith('|') or
                    re.match(r'\s*([-*]|\d+\.) ', line) is not None or line.startswith('#'))
        if new_unit and cur:
            out.append((start, '\n'.join(cur), False))
            cur = []
        if line.strip() == '':
            continue
        if line.startswith('|') or line.startswith('#'):
            out.append((n, line, False))
            continue
        if not cur:
            start = n
        cur.append(line)
    if cur:
        out.append((start, '\n'.join(cur), False))
    return out


def code_spans(text, all_code):
    if all_code:
        return [(0, len(text))]
    spans = []
    for m in re.finditer(r'`([^`]+)`', text):
        spans.append((m.start(1), m.end(1)))
    return spans


def in_spans(pos, spans):
    return any(a <= pos < b for a, b in spans)


def main(argv):
    list_unattributed = '--list-unattributed' in argv
    args = [a for a in argv if a != '--list-unattributed']
    if len(args) < 2:
        print(__doc__.split('\n\n')[1], file=sys.stderr)
        return 2
    tools_dir, docs = args[0], args[1:]
    readme = docs[0]
    rows = tool_table(readme)
    bad = 0
    if not rows:
        fail('%s: no tool table ("| program | what it does | source |")' % readme)
        return 1
    layout_done = os.path.isdir('sim_host/tools')
    helps = {}
    for prog, src, n in rows:
        if layout_done and not os.path.isfile(src):
            fail('%s:%d: %s: source %s does not exist' % (readme, n, prog, src))
            bad += 1
        exe = os.path.join(tools_dir, prog)
        if not layout_done and not os.path.isfile(src) and not os.access(exe, os.X_OK):
            # Before sim_host/tools/ exists the table's sources are the planned
            # ones: a program that is neither built nor there is not checked.
            print('doc_options: %s:%d: %s: neither built nor at %s yet (sim_host/tools/ '
                  'not there): not checked' % (readme, n, prog, src))
            continue
        if not os.access(exe, os.X_OK):
            fail('%s:%d: %s: not built in %s' % (readme, n, prog, tools_dir))
            bad += 1
            continue
        try:
            r = subprocess.run([exe, '--help'], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               timeout=30, stdin=subprocess.DEVNULL)
        except subprocess.TimeoutExpired:
            fail('%s --help: no answer within 30 s' % prog)
            bad += 1
            continue
        text = r.stdout.decode('utf-8', 'replace')
        if r.returncode != 0:
            fail('%s --help: exit status %d, not 0' % (prog, r.returncode))
            bad += 1
        if text.strip() == '':
            fail('%s --help: nothing on standard output' % prog)
            bad += 1
        helps[prog] = set(OPTION.findall(text)) | {'--help'}

    ours = sorted(helps, key=len, reverse=True)
    names = [(p, True) for p in ours] + [(e, False) for e in EXTERNAL]
    name_re = re.compile(r'(?<![\w.-])(' + '|'.join(re.escape(p) for p, _ in names) +
                         r'|[\w./-]+\.(?:sh|py))(?![\w-]|\.(?:c|h|md|dbc|txt|csv|elf|mk)\b)')
    checked = 0
    for doc in docs:
        for line0, text, all_code in blocks(doc):
            spans = code_spans(text, all_code)
            events = []
            for m in name_re.finditer(text):
                name = m.group(1)
                if name in CODE_ONLY and not in_spans(m.start(), spans):
                    continue
                events.append((m.start(), 'cmd', name))
            for m in OPTION.finditer(text):
                if in_spans(m.start(), spans):
                    events.append((m.start(), 'opt', m.group(1)))
            events.sort()
            cmd = None
            for pos, kind, val in events:
                if kind == 'cmd':
                    cmd = val
                    continue
                ln = line0 + text.count('\n', 0, pos)
                if cmd is None:
                    if list_unattributed:
                        print('%s:%d: %s: no command before it' % (doc, ln, val))
                    continue
                if cmd not in helps:
                    continue
                checked += 1
                if val not in helps[cmd]:
                    fail('%s:%d: %s %s: not in `%s --help`' % (doc, ln, cmd, val, cmd))
                    bad += 1
    print('doc_options: %d tools answer --help; %d options named in %d documents checked; %d problems'
          % (len(helps), checked, len(docs), bad))
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))

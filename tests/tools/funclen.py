#!/usr/bin/env python3
"""funclen.py - the lengths of the C functions in the given folders.

    funclen.py [--top N] [--max-lines N] [--max-main N] [--exempt FILE] DIR...

A function's length is its lines from the one holding its name to its
closing brace.  --top N prints the N longest.  With --max-lines and
--max-main it exits 1 if a function (other than main) or a main is longer,
naming each; --exempt FILE lists paths (one a line, # comments) whose
functions are exempt: generated tables, the SIMD kernels.
"""
import argparse
import os
import re
import sys


def strip(text):
    """Comments and string/char literals blanked, newlines kept."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + re.sub(r"[^\n]", " ", text[i + 1:j]) + c)
            i = j + 1
        elif c == "#" and (i == 0 or text[i - 1] == "\n"):
            # a preprocessor line, with its continuations
            j = i
            while True:
                k = text.find("\n", j)
                if k < 0:
                    k = n
                    break
                if text[k - 1] != "\\":
                    break
                j = k + 1
            out.append(re.sub(r"[^\n]", " ", text[i:k]))
            i = k
        else:
            out.append(c)
            i += 1
    return "".join(out)


def header_name(head):
    """The name of the function whose header ends head: the identifier
    before the parameter list that closes it, or None."""
    h = head.rstrip()
    if not h.endswith(")"):
        return None, 0
    depth = 0
    for i in range(len(h) - 1, -1, -1):
        if h[i] == ")":
            depth += 1
        elif h[i] == "(":
            depth -= 1
            if depth == 0:
                m = re.search(r"([A-Za-z_]\w*)\s*$", h[:i])
                if not m or m.group(1) in ("if", "while", "for", "switch", "return", "sizeof"):
                    return None, 0
                return m.group(1), m.start(1)
    return None, 0


def functions(path):
    """(name, first line, last line) of each function defined in path."""
    with open(path, encoding="utf-8", errors="replace") as f:
        text = strip(f.read())
    found, depth, start = [], 0, 0  # start: offset after the last top-level ; or }
    i = 0
    while i < len(text):
        c = text[i]
        if c == "{":
            if depth == 0:
                head = text[start:i]
                name, at = header_name(head)
                if name and "=" not in head[:at]:
                    first = text.count("\n", 0, start + at) + 1
                    found.append([name, first, None, i])
            depth += 1
        elif c == "}":
            depth -= 1
            if depth == 0:
                if found and found[-1][2] is None and found[-1][3] < i:
                    found[-1][2] = text.count("\n", 0, i) + 1
                start = i + 1
        elif c == ";" and depth == 0:
            start = i + 1
        i += 1
    return [(n, a, b) for n, a, b, _ in found if b is not None]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--top", type=int, default=0)
    ap.add_argument("--max-lines", type=int)
    ap.add_argument("--max-main", type=int)
    ap.add_argument("--exempt")
    ap.add_argument("dirs", nargs="+")
    a = ap.parse_args()
    exempt = set()
    if a.exempt:
        with open(a.exempt) as f:
            exempt = {l.split("#")[0].strip() for l in f} - {""}
    rows = []
    for d in a.dirs:
        for root, _, files in os.walk(d):
            for fn in sorted(files):
                if fn.endswith((".c", ".h")):
                    p = os.path.join(root, fn)
                    for name, first, last in functions(p):
                        rows.append((last - first + 1, p, first, name))
    rows.sort(key=lambda r: (-r[0], r[1], r[2]))
    for n, p, first, name in rows[: a.top]:
        print(f"{n:5d}  {p}:{first}  {name}")
    bad = 0
    for n, p, first, name in rows:
        if p in exempt:
            continue
        limit = a.max_main if name == "main" else a.max_lines
        if limit is not None and n > limit:
            print(f"funclen: {p}:{first}: {name} is {n} lines, more than {limit}", file=sys.stderr)
            bad += 1
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()

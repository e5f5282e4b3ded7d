#!/usr/bin/env python3
"""layers.py - the layering of lanray's code, checked from its #include lines.

    layers.py [--root DIR]          checks; exit 1 naming every back-edge
    layers.py [--root DIR] --dot    the folder graph (graphviz dot) on stdout

common/ is cut into folders, lowest first (docs/architecture.md says what
each holds); a file may include its own folder's headers and those of
lower layers, never a higher one.  server/ and client/ sit above common/
and beside each other (neither includes the other); tools/ (the programs'
mains, benchmarks) may use everything.  Includes are written FOLDER/NAME.h
for common/ (-Icommon), so the folder of an include is in its name.

The segment scheduler (server/scheduler.*) is pure logic that the server,
the tests and the simulator drive: it may include base/ and the segment
type (render/segment.h), nothing of the wire or the scene."""
import os
import re
import sys

LAYERS = ["base", "image", "geom", "shading", "bvh", "model", "scene", "render", "net", "app"]
RANK = {f: i for i, f in enumerate(LAYERS)}
RANK.update({"server": len(LAYERS), "client": len(LAYERS), "tools": len(LAYERS) + 1})
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)


def sources(root):
    for top in ["common", "server", "client", "tools"]:
        for d, _, files in sorted(os.walk(os.path.join(root, top))):
            for f in sorted(files):
                if f.endswith((".c", ".h")):
                    yield os.path.join(d, f)


def folder_of(root, path):
    rel = os.path.relpath(path, root).split(os.sep)
    return rel[1] if rel[0] == "common" else rel[0]


def include_folder(root, path, inc):
    if "/" in inc:
        return inc.split("/")[0]
    here = os.path.dirname(path)
    if os.path.exists(os.path.join(here, inc)):
        return folder_of(root, os.path.join(here, inc))
    for top in ["server", "client"]:  # -Iserver -Iclient
        if os.path.exists(os.path.join(root, top, inc)):
            return top
    return None


def edges(root):
    for path in sources(root):
        src = folder_of(root, path)
        text = open(path, encoding="utf-8", errors="replace").read()
        for m in INCLUDE.finditer(text):
            dst = include_folder(root, path, m.group(1))
            if dst is not None and dst != src:
                line = text.count("\n", 0, m.start()) + 1
                yield path, line, src, dst, m.group(1)


SCHEDULER = ("server/scheduler.c", "server/scheduler.h")
SCHEDULER_MAY = re.compile(r"^(base/[\w.]+|render/segment\.h|scheduler\.h)$")


def scheduler_problems(root):
    """Includes of the scheduler beyond base/ and its segment type."""
    for rel in SCHEDULER:
        path = os.path.join(root, rel)
        if not os.path.exists(path):
            continue
        text = open(path, encoding="utf-8", errors="replace").read()
        for m in INCLUDE.finditer(text):
            if not SCHEDULER_MAY.match(m.group(1)):
                line = text.count("\n", 0, m.start()) + 1
                yield "%s:%d: the scheduler (pure logic) includes %s: it may use base/ and render/segment.h only" % (
                    path, line, m.group(1))


def main():
    args = sys.argv[1:]
    root = "."
    if "--root" in args:
        root = args[args.index("--root") + 1]
    found = list(edges(root))
    if "--dot" in args:
        pairs = sorted({(s, d) for _, _, s, d, _ in found})
        print("digraph layers {\n  rankdir=BT; node [shape=box, fontname=Helvetica];")
        for s, d in pairs:
            print('  "%s" -> "%s";' % (s, d))
        print("}")
        return 0
    bad = 0
    for path, line, src, dst, inc in found:
        if src not in RANK or dst not in RANK:
            print("%s:%d: includes %s from an unknown folder (%s -> %s)" % (path, line, inc, src, dst))
            bad += 1
        elif RANK[dst] >= RANK[src]:
            print("%s:%d: %s (layer %s) includes %s, of layer %s above or beside it" % (path, line, src, src, inc, dst))
            bad += 1
    for problem in scheduler_problems(root):
        print(problem)
        bad += 1
    if bad:
        print("layers: %d bad include%s (docs/architecture.md: a folder includes only itself and the layers below;"
              " the scheduler only base/ and render/segment.h)" % (bad, "" if bad == 1 else "s"))
        return 1
    print("layers: %d includes across folders, all downward; the scheduler includes no more than base/ and its segment type"
          % len(found))
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""ptyrun.py [--for S] [--until REGEX] CMD ARGS... - runs a command with its
standard error (and output) on a pseudo-terminal, as a user at a terminal
would, and prints what it wrote there (carriage returns kept); exits with
the command's status.  The progress tests use it: progress lines appear
only on a terminal.  With --for, the command is stopped (SIGTERM) after S
seconds; with --until, as soon as what it wrote matches REGEX: a long
render shows its first progress line, or shows none in its first seconds,
without the test waiting for its end (exit status 0 when stopped so)."""
import os
import pty
import re
import select
import signal
import sys
import time

args = sys.argv[1:]
limit, until = None, None
while args and args[0] in ("--for", "--until"):
    if args[0] == "--for":
        limit = float(args[1])
    else:
        until = re.compile(args[1])
    args = args[2:]
pid, fd = pty.fork()
if pid == 0:
    os.execvp(args[0], args)
out = b""
t0 = time.monotonic()
stopped = False
while True:
    wait = None if limit is None else max(0.0, limit - (time.monotonic() - t0))
    ready, _, _ = select.select([fd], [], [], wait)
    if not ready:  # --for ran out
        os.kill(pid, signal.SIGTERM)
        stopped = True
        break
    try:
        chunk = os.read(fd, 65536)
    except OSError:
        break
    if not chunk:
        break
    out += chunk
    if until and until.search(out.decode("utf-8", "replace")):
        os.kill(pid, signal.SIGTERM)
        stopped = True
        break
_, status = os.waitpid(pid, 0)
sys.stdout.write(out.decode("utf-8", "replace"))
sys.exit(0 if stopped else os.waitstatus_to_exitcode(status))

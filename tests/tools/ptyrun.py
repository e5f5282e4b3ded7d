#!/usr/bin/env python3
"""ptyrun.py CMD ARGS... - runs a command with its standard error (and
output) on a pseudo-terminal, as a user at a terminal would, and prints what
it wrote there (carriage returns kept); exits with the command's status.
The progress tests use it: progress lines appear only on a terminal."""
import os
import pty
import sys

pid, fd = pty.fork()
if pid == 0:
    os.execvp(sys.argv[1], sys.argv[1:])
out = b""
while True:
    try:
        chunk = os.read(fd, 65536)
    except OSError:
        break
    if not chunk:
        break
    out += chunk
_, status = os.waitpid(pid, 0)
sys.stdout.write(out.decode("utf-8", "replace"))
sys.exit(os.waitstatus_to_exitcode(status))

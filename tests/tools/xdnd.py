#!/usr/bin/env python3
"""xdnd.py WINDOW X Y PATH: drops the file PATH on the X window WINDOW at
the screen point X, Y, as a file manager does (the XDND protocol, version
5: enter, position, the target's status, drop, the path handed over as
text/uri-list through the XdndSelection, the target's finish).  Exits 0
once the target said it finished, 1 with the reason otherwise (the target
refused, or said nothing within 5 s)."""
import ctypes
import os
import sys
import time
import urllib.parse

from x11 import CLIENT_MESSAGE, SELECTION_NOTIFY, SELECTION_REQUEST, Event, X11


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    target, x, y, path = int(sys.argv[1], 0), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    # a file manager's URI: an absolute path (file://models/x would name a host "models")
    uri = ("file://" + urllib.parse.quote(os.path.abspath(path)) + "\r\n").encode()
    d = X11("xdnd")
    a = {n: d.atom(n) for n in ("XdndEnter", "XdndPosition", "XdndStatus", "XdndDrop", "XdndFinished",
                                "XdndSelection", "XdndActionCopy", "text/uri-list")}
    d.x.XSetSelectionOwner(d.dpy, ctypes.c_ulong(a["XdndSelection"]), d.win, ctypes.c_ulong(0))

    def send(kind, *longs):
        ev = Event()
        ev.client.type, ev.client.display, ev.client.window = CLIENT_MESSAGE, d.dpy.value, target
        ev.client.message_type, ev.client.format = a[kind], 32
        for i, v in enumerate(longs):
            ev.client.l[i] = v
        d.send(target, ev)

    send("XdndEnter", d.win.value, 5 << 24, a["text/uri-list"], 0, 0)
    send("XdndPosition", d.win.value, 0, (x << 16) | y, 0, a["XdndActionCopy"])
    dropped = False
    deadline = time.time() + 5
    while True:
        ev = d.next_event(deadline, 0.01)
        if ev is None:
            sys.exit("xdnd: no %s within 5 s" % ("finish" if dropped else "status"))
        if ev.type == CLIENT_MESSAGE and ev.client.message_type == a["XdndStatus"]:
            if not ev.client.l[1] & 1:
                sys.exit("xdnd: the window does not take the file")
            if not dropped:
                send("XdndDrop", d.win.value, 0, 0)
                dropped = True
        elif ev.type == SELECTION_REQUEST:
            r = ev.request
            d.x.XChangeProperty(d.dpy, ctypes.c_ulong(r.requestor), ctypes.c_ulong(r.property),
                                ctypes.c_ulong(r.target), 8, 0, ctypes.c_char_p(uri), len(uri))
            n = Event()
            n.notify.type, n.notify.display, n.notify.requestor = SELECTION_NOTIFY, d.dpy.value, r.requestor
            n.notify.selection, n.notify.target, n.notify.property, n.notify.time = (r.selection, r.target,
                                                                                     r.property, r.time)
            d.send(r.requestor, n)
        elif ev.type == CLIENT_MESSAGE and ev.client.message_type == a["XdndFinished"]:
            d.close()
            return 0


if __name__ == "__main__":
    sys.exit(main())

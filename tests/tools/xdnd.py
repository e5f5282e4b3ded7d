#!/usr/bin/env python3
"""xdnd.py WINDOW X Y PATH: drops the file PATH on the X window WINDOW at
the screen point X, Y, as a file manager does (the XDND protocol, version
5: enter, position, the target's status, drop, the path handed over as
text/uri-list through the XdndSelection, the target's finish).  Talks to
libX11 through ctypes: nothing to install beyond what SDL already needs.
Exits 0 once the target said it finished, 1 with the reason otherwise
(the target refused, or said nothing within 5 s)."""
import ctypes
import ctypes.util
import os
import sys
import time
import urllib.parse

CLIENT_MESSAGE, SELECTION_REQUEST, SELECTION_NOTIFY = 33, 30, 31


class ClientMessage(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int), ("serial", ctypes.c_ulong), ("send_event", ctypes.c_int),
                ("display", ctypes.c_void_p), ("window", ctypes.c_ulong), ("message_type", ctypes.c_ulong),
                ("format", ctypes.c_int), ("l", ctypes.c_long * 5)]


class SelectionRequest(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int), ("serial", ctypes.c_ulong), ("send_event", ctypes.c_int),
                ("display", ctypes.c_void_p), ("owner", ctypes.c_ulong), ("requestor", ctypes.c_ulong),
                ("selection", ctypes.c_ulong), ("target", ctypes.c_ulong), ("property", ctypes.c_ulong),
                ("time", ctypes.c_ulong)]


class SelectionNotify(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int), ("serial", ctypes.c_ulong), ("send_event", ctypes.c_int),
                ("display", ctypes.c_void_p), ("requestor", ctypes.c_ulong), ("selection", ctypes.c_ulong),
                ("target", ctypes.c_ulong), ("property", ctypes.c_ulong), ("time", ctypes.c_ulong)]


class Event(ctypes.Union):
    _fields_ = [("type", ctypes.c_int), ("client", ClientMessage), ("request", SelectionRequest),
                ("notify", SelectionNotify), ("pad", ctypes.c_long * 24)]


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    target, x, y, path = int(sys.argv[1], 0), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    # a file manager's URI: an absolute path (file://models/x would name a host "models")
    uri = ("file://" + urllib.parse.quote(os.path.abspath(path)) + "\r\n").encode()
    x11 = ctypes.CDLL(ctypes.util.find_library("X11") or "libX11.so.6")
    x11.XOpenDisplay.restype = ctypes.c_void_p
    x11.XDefaultRootWindow.restype = ctypes.c_ulong
    x11.XCreateSimpleWindow.restype = ctypes.c_ulong
    x11.XInternAtom.restype = ctypes.c_ulong
    for f in ("XDefaultRootWindow", "XCreateSimpleWindow", "XInternAtom", "XSetSelectionOwner", "XSendEvent",
              "XFlush", "XPending", "XNextEvent", "XChangeProperty", "XCloseDisplay"):
        getattr(x11, f).argtypes = None
    dpy = ctypes.c_void_p(x11.XOpenDisplay(None))
    if not dpy:
        sys.exit("xdnd: no X display")
    atom = lambda name: ctypes.c_ulong(x11.XInternAtom(dpy, name.encode(), 0))
    names = ("XdndAware", "XdndEnter", "XdndPosition", "XdndStatus", "XdndDrop", "XdndFinished", "XdndSelection",
             "XdndActionCopy", "text/uri-list")
    a = {n: atom(n).value for n in names}
    root = ctypes.c_ulong(x11.XDefaultRootWindow(dpy))
    src = ctypes.c_ulong(x11.XCreateSimpleWindow(dpy, root, 0, 0, 1, 1, 0, ctypes.c_ulong(0), ctypes.c_ulong(0)))
    x11.XSetSelectionOwner(dpy, ctypes.c_ulong(a["XdndSelection"]), src, ctypes.c_ulong(0))

    def send(kind, *longs):
        ev = Event()
        ev.client.type, ev.client.display, ev.client.window = CLIENT_MESSAGE, dpy.value, target
        ev.client.message_type, ev.client.format = a[kind], 32
        for i, v in enumerate(longs):
            ev.client.l[i] = v
        x11.XSendEvent(dpy, ctypes.c_ulong(target), 0, ctypes.c_long(0), ctypes.byref(ev))
        x11.XFlush(dpy)

    send("XdndEnter", src.value, 5 << 24, a["text/uri-list"], 0, 0)
    send("XdndPosition", src.value, 0, (x << 16) | y, 0, a["XdndActionCopy"])
    dropped = False
    deadline = time.time() + 5
    while time.time() < deadline:
        if not x11.XPending(dpy):
            time.sleep(0.01)
            continue
        ev = Event()
        x11.XNextEvent(dpy, ctypes.byref(ev))
        if ev.type == CLIENT_MESSAGE and ev.client.message_type == a["XdndStatus"]:
            if not ev.client.l[1] & 1:
                sys.exit("xdnd: the window does not take the file")
            if not dropped:
                send("XdndDrop", src.value, 0, 0)
                dropped = True
        elif ev.type == SELECTION_REQUEST:
            r = ev.request
            x11.XChangeProperty(dpy, ctypes.c_ulong(r.requestor), ctypes.c_ulong(r.property),
                                ctypes.c_ulong(r.target), 8, 0, ctypes.c_char_p(uri), len(uri))
            n = Event()
            n.notify.type, n.notify.display, n.notify.requestor = SELECTION_NOTIFY, dpy.value, r.requestor
            n.notify.selection, n.notify.target, n.notify.property, n.notify.time = (r.selection, r.target,
                                                                                     r.property, r.time)
            x11.XSendEvent(dpy, ctypes.c_ulong(r.requestor), 0, ctypes.c_long(0), ctypes.byref(n))
            x11.XFlush(dpy)
        elif ev.type == CLIENT_MESSAGE and ev.client.message_type == a["XdndFinished"]:
            x11.XCloseDisplay(dpy)
            return 0
    sys.exit("xdnd: no %s within 5 s" % ("finish" if dropped else "status"))


if __name__ == "__main__":
    sys.exit(main())

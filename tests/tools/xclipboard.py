#!/usr/bin/env python3
"""xclipboard.py: prints the X clipboard's text (the CLIPBOARD selection
as UTF8_STRING), as a paste would get it; exits 1 where nothing owns it or
its owner says nothing within 5 s."""
import ctypes
import sys
import time

from x11 import SELECTION_NOTIFY, X11


def main():
    d = X11("xclipboard")
    prop = d.atom("LANRAY_PASTE")
    d.x.XConvertSelection(d.dpy, ctypes.c_ulong(d.atom("CLIPBOARD")), ctypes.c_ulong(d.atom("UTF8_STRING")),
                          ctypes.c_ulong(prop), d.win, ctypes.c_ulong(0))
    d.x.XFlush(d.dpy)
    deadline = time.time() + 5
    while True:
        ev = d.next_event(deadline, 0.01)
        if ev is None:
            sys.exit("xclipboard: no answer within 5 s")
        if ev.type == SELECTION_NOTIFY:
            break
    if not ev.notify.property:
        sys.exit("xclipboard: nothing on the clipboard")
    kind, fmt = ctypes.c_ulong(), ctypes.c_int()
    n, left, data = ctypes.c_ulong(), ctypes.c_ulong(), ctypes.c_void_p()
    d.x.XGetWindowProperty(d.dpy, d.win, ctypes.c_ulong(prop), ctypes.c_long(0), ctypes.c_long(1 << 20), 1,
                           ctypes.c_ulong(0), ctypes.byref(kind), ctypes.byref(fmt), ctypes.byref(n),
                           ctypes.byref(left), ctypes.byref(data))
    text = ctypes.string_at(data, n.value).decode("utf-8", "replace") if data else ""
    if data:
        d.x.XFree(data)
    d.close()
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""xwmstate.py WINDOW add|remove STATE... - asks the window manager to
change a window's state (EWMH _NET_WM_STATE: maximized_vert,
maximized_horz, fullscreen ...), as a title bar's maximise button or a
pager does: a client message to the root window, which the window manager
answers by resizing the window.  (The desktop test, tests/cli/desktop.sh.)"""
import sys

from x11 import CLIENT_MESSAGE, ClientMessage, Event, X11

SUBSTRUCTURE_REDIRECT_AND_NOTIFY = (1 << 20) | (1 << 19)


def main():
    if len(sys.argv) < 4 or sys.argv[2] not in ("add", "remove") or len(sys.argv) > 5:
        sys.exit("usage: xwmstate.py WINDOW add|remove STATE [STATE]")
    x = X11("xwmstate.py")
    ev = Event()
    ev.client = ClientMessage(type=CLIENT_MESSAGE, send_event=1, window=int(sys.argv[1], 0),
                              message_type=x.atom("_NET_WM_STATE"), format=32)
    ev.client.l[0] = 1 if sys.argv[2] == "add" else 0
    for i, state in enumerate(sys.argv[3:]):
        ev.client.l[1 + i] = x.atom("_NET_WM_STATE_" + state.upper())
    ev.client.l[3] = 1  # from an application (a pager would say 2)
    x.send(x.x.XDefaultRootWindow(x.dpy), ev, SUBSTRUCTURE_REDIRECT_AND_NOTIFY)
    x.close()


if __name__ == "__main__":
    main()

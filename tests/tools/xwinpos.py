#!/usr/bin/env python3
"""xwinpos.py WINDOW - prints "X Y", where the window's own top-left pixel
is on the screen.  (xdotool getwindowgeometry, under a window manager that
puts the window in a frame of its own, adds the frame's offset a second
time: the desktop test, tests/cli/desktop.sh, asks here instead.)"""
import ctypes
import sys

from x11 import X11


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: xwinpos.py WINDOW")
    x = X11("xwinpos.py")
    rx, ry, child = ctypes.c_int(), ctypes.c_int(), ctypes.c_ulong()
    root = x.x.XDefaultRootWindow(x.dpy)
    if not x.x.XTranslateCoordinates(x.dpy, ctypes.c_ulong(int(sys.argv[1], 0)), ctypes.c_ulong(root), 0, 0,
                                     ctypes.byref(rx), ctypes.byref(ry), ctypes.byref(child)):
        sys.exit("xwinpos.py: the window is not on the root window's screen")
    print(rx.value, ry.value)
    x.close()


if __name__ == "__main__":
    main()

"""x11.py - libX11 through ctypes for the window tests' tools (xdnd.py,
xclipboard.py): the display, atoms, a window of their own and the events
they read and send.  Nothing to install beyond what SDL already needs."""
import ctypes
import ctypes.util
import sys

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


class X11:
    """The display (DISPLAY), its atoms by name, and a 1x1 window of our own (win)."""

    def __init__(self, prog):
        x = ctypes.CDLL(ctypes.util.find_library("X11") or "libX11.so.6")
        x.XOpenDisplay.restype = ctypes.c_void_p
        for f in ("XDefaultRootWindow", "XCreateSimpleWindow", "XInternAtom"):
            getattr(x, f).restype = ctypes.c_ulong
        self.x = x
        self.dpy = ctypes.c_void_p(x.XOpenDisplay(None))
        if not self.dpy:
            sys.exit(prog + ": no X display")
        root = ctypes.c_ulong(x.XDefaultRootWindow(self.dpy))
        self.win = ctypes.c_ulong(x.XCreateSimpleWindow(self.dpy, root, 0, 0, 1, 1, 0, ctypes.c_ulong(0),
                                                        ctypes.c_ulong(0)))

    def atom(self, name):
        return self.x.XInternAtom(self.dpy, name.encode(), 0)

    def next_event(self, deadline, sleep):
        """The next event, or None once the deadline (time.time()) passed."""
        import time
        while time.time() < deadline:
            if self.x.XPending(self.dpy):
                ev = Event()
                self.x.XNextEvent(self.dpy, ctypes.byref(ev))
                return ev
            time.sleep(sleep)
        return None

    def send(self, window, ev, mask=0):
        self.x.XSendEvent(self.dpy, ctypes.c_ulong(window), 0, ctypes.c_long(mask), ctypes.byref(ev))
        self.x.XFlush(self.dpy)

    def close(self):
        self.x.XCloseDisplay(self.dpy)

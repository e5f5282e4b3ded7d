/* net.h - the socket layer: listening, accepting and dialing TCP over IPv4
 * or IPv6.  Names go through getaddrinfo, so "localhost", "::1" and
 * "192.168.1.5" all work; every socket it returns is non-blocking with
 * TCP_NODELAY (the protocol's small packets must not wait for Nagle). */
#ifndef LANRAY_NET_H
#define LANRAY_NET_H

#include <stddef.h>

#include "base/err.h"

typedef struct {
    int fd;
    int port;         /* the port bound (the one the system chose for port 0) */
    char shown[80];   /* the address as logs and scripts read it: 127.0.0.1:7878, [::1]:7878 */
} NetListener;

/* Listens on addr (a name or an address) and port (0: any free one). */
int net_listen(const char *addr, int port, NetListener *out, Err *err);
/* Whether addr names only this machine (127.0.0.0/8, ::1, "localhost"),
 * without binding anything: a server refuses to listen on anything else
 * without a token. */
int net_is_loopback(const char *addr);
/* A waiting connection, set up; peer gets its address.  -1 when none waits. */
int net_accept(int listen_fd, char *peer, size_t size);
/* Connects (blocking) to host:port; returns the socket, set up, or -1. */
int net_dial(const char *host, int port, Err *err);
/* Non-blocking with TCP_NODELAY. */
int net_setup(int fd);

#endif

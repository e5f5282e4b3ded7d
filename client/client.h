/* client.h - the render client: connects to a server, renders the segments
 * it is given with the core's thread pool, sends the pixels back, and
 * reconnects with backoff when the server goes away. */
#ifndef LANRAY_CLIENT_H
#define LANRAY_CLIENT_H

#include <signal.h>
#include <stdint.h>

#include "base/err.h"

typedef struct {
    const char *host;
    int port;
    int threads;
    const char *token;  /* NULL: none */
    int quiet;
    int reconnect;      /* 0: end after the first session */
} ClientConfig;

/* What a run did, for the closing line the program prints. */
typedef struct {
    uint64_t segments, pixels;
    uint32_t sessions; /* connections that got through the handshake */
    uint64_t scenes;   /* scene descriptions decoded (a frame of a new view needs none) */
    uint64_t trees;    /* top-level trees built for them (a new description whose boxes did not change needs none) */
} ClientStats;

/* Runs until *stop becomes non-zero (or, without reconnect, the session
 * ends).  Returns 0, or -1 when the server refused us (wrong token, protocol
 * version, precision: retrying cannot help then) or, without reconnect,
 * when no session got through the handshake (no server, a timeout).  stats
 * may be NULL. */
int client_run(const ClientConfig *cfg, volatile sig_atomic_t *stop, ClientStats *stats, Err *err);

/* One session on an already connected socket (closed at the end): no
 * dialing, no reconnecting.  The packet fuzzer and tests use it with one end
 * of a socketpair.  Returns as client_run does; err says why the session
 * ended. */
int client_run_fd(const ClientConfig *cfg, int fd, volatile sig_atomic_t *stop, ClientStats *stats, Err *err);

#endif

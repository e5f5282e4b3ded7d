/* conn.h - a connection's packets: framing and buffering.
 *
 * Every packet starts with an 8-byte header: u32 type, u32 total size
 * (header included), host byte order; its body's layout is msg.h's, and
 * docs/protocol.md lists the packets.  A Conn buffers one non-blocking socket: incoming bytes are cut into
 * packets only after the header's size has been checked against the limit
 * for its type, so a peer that lies about sizes cannot make us allocate. */
#ifndef LANRAY_CONN_H
#define LANRAY_CONN_H

#include <stddef.h>
#include <stdint.h>

#include "base/cursor.h"
#include "base/err.h"
#include "net/msg.h"

typedef struct {
    int fd;
    /* input: one packet at a time */
    uint8_t head[PROTO_HEADER];
    uint32_t head_got;
    uint8_t *body;
    uint32_t body_size, body_got, body_cap;
    uint32_t type;
    /* output queue */
    uint8_t *out;
    size_t out_len, out_sent, out_cap;
    uint64_t bytes_in, bytes_out;
} Conn;

void conn_init(Conn *c, int fd);
void conn_close(Conn *c);
/* Reads what the socket has.  Returns 1 when a whole packet is ready
 * (c->type, c->body, c->body_size), 0 when more bytes are needed, -1 on
 * error or end of stream (with a reason in err).  Call again after using the
 * packet: the next call starts on the following one. */
int conn_read(Conn *c, Err *err);
/* What may wait in a connection's output queue: past it, the peer is not
 * reading, and the connection is dropped rather than the memory grown. */
#define CONN_MAX_QUEUE ((size_t)1 << 30)

/* Queues an encoded packet (msg.h; the header added here, its tail copied
 * into the queue); fails if the queue would exceed max_queue. */
int conn_send_msg(Conn *c, const MsgOut *m, size_t max_queue, Err *err);
/* Writes what the socket takes; returns bytes still queued, or -1 on error. */
long conn_flush(Conn *c, Err *err);
static inline size_t conn_pending(const Conn *c) { return c->out_len - c->out_sent; }

#endif

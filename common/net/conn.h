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
    /* input: the bytes read ahead, [in_at, in_len) of in, taken by recv
     * as many as the buffer holds (several packets a call); the packet
     * handed out (type, body, body_size) points into it */
    uint8_t *in;
    size_t in_at, in_len, in_cap;
    size_t handed; /* bytes of the packet handed out last, dropped at the next read */
    int drained;   /* the last recv filled less than it could: the socket had no more */
    const uint8_t *body;
    uint32_t body_size;
    uint32_t type;
    /* output queue */
    uint8_t *out;
    size_t out_len, out_sent, out_cap;
    uint64_t bytes_in, bytes_out;
} Conn;

void conn_init(Conn *c, int fd);
void conn_close(Conn *c);
/* Reads what the socket has.  Returns 1 when a whole packet is ready
 * (c->type, c->body, c->body_size; the body valid until the next call), 0
 * when more bytes are needed, -1 on error or end of stream (with a reason
 * in err).  Call again after using the packet: the next call starts on the
 * following one, which may already be in the buffer (no system call).
 * After a recv that took less than it could (the socket was emptied), the
 * next call that needs more bytes returns 0 without another recv: the
 * caller waits on poll() for the socket before it calls again (a loop that
 * calls it twice in a row without poll sees that 0 once).
 * Reads ahead CONN_READ_AHEAD bytes at a time; a packet larger than that is
 * given room only once its header's size passed the type's limit. */
#define CONN_READ_AHEAD ((size_t)64 << 10)
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
/* Whether a whole packet read ahead waits in the buffer past the one handed
 * out: the socket may have nothing more to say (poll() stays quiet), so a
 * loop must call conn_read again before it waits on poll.  (A part of a
 * packet is not: its rest comes through the socket.) */
int conn_buffered(const Conn *c);

#endif

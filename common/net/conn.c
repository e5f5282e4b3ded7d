/* conn.c - see conn.h. */
#include "net/conn.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

void conn_init(Conn *c, int fd)
{
    memset(c, 0, sizeof *c);
    c->fd = fd;
}

void conn_close(Conn *c)
{
    if (c->fd >= 0)
        close(c->fd);
    free(c->in);
    free(c->out);
    memset(c, 0, sizeof *c);
    c->fd = -1;
}

/* Room for `need` bytes from in_at on: what is left moved to the start,
 * the buffer grown to need (checked by the caller against the packet
 * limits), and after a big packet shrunk back to the read-ahead size. */
static int room(Conn *c, size_t need, Err *err)
{
    const size_t left = c->in_len - c->in_at;
    if (c->in_at) {
        memmove(c->in, c->in + c->in_at, left);
        c->in_len = left, c->in_at = 0;
    }
    size_t cap = need > CONN_READ_AHEAD ? need : CONN_READ_AHEAD;
    if (cap > c->in_cap || (c->in_cap > 4 * CONN_READ_AHEAD && cap < c->in_cap && left <= cap)) {
        uint8_t *p = realloc(c->in, cap);
        if (!p)
            return err_set(err, "out of memory for a %zu-byte packet", need);
        c->in = p;
        c->in_cap = cap;
    }
    return 0;
}

/* The header at `at` of the buffer (at least PROTO_HEADER bytes there):
 * its type and size, checked against the type's limits (-1 and why, in err
 * where there is one, when they refuse it). */
static int header_at(const Conn *c, size_t at, uint32_t *type, uint32_t *size, Err *err)
{
    memcpy(type, c->in + at, 4);
    memcpy(size, c->in + at + 4, 4);
    uint32_t max = msg_max_size(*type);
    if (max == 0)
        return err_set(err, "packet of unknown type %u", *type);
    if (*size < msg_min_size(*type) || *size > max)
        return err_set(err, "%s packet claims %u bytes, allowed %u..%u", msg_type_name(*type), *size,
                       msg_min_size(*type), max);
    return 0;
}

int conn_buffered(const Conn *c)
{
    const size_t at = c->in_at + c->handed;
    if (c->in_len - at < PROTO_HEADER)
        return 0;
    uint32_t type, size;
    /* a header the limits refuse counts as ready: conn_read then says why */
    return header_at(c, at, &type, &size, NULL) || size <= c->in_len - at;
}

int conn_read(Conn *c, Err *err)
{
    /* the packet handed out last time is finished */
    c->in_at += c->handed;
    c->handed = 0;
    if (c->in_at == c->in_len)
        c->in_at = c->in_len = 0;
    for (;;) {
        const size_t have = c->in_len - c->in_at;
        size_t need = PROTO_HEADER;
        if (have >= PROTO_HEADER) {
            uint32_t size;
            if (header_at(c, c->in_at, &c->type, &size, err))
                return -1;
            if (have >= size) {
                c->body = c->in + c->in_at + PROTO_HEADER;
                c->body_size = size - PROTO_HEADER;
                c->handed = size;
                return 1;
            }
            need = size;
        }
        /* the socket was emptied by the last recv: no call that would
         * only say EAGAIN (one a round per connection under load); the
         * caller's poll says when more has come */
        if (c->drained) {
            c->drained = 0;
            return 0;
        }
        if (c->in_at + need > c->in_cap && room(c, need, err))
            return -1;
        const size_t space = c->in_cap - c->in_len;
        ssize_t n = recv(c->fd, c->in + c->in_len, space, 0);
        if (n == 0)
            return !have ? err_set(err, "connection closed by peer")
                   : have < PROTO_HEADER
                       ? err_set(err, "connection closed by peer in the middle of a packet's header")
                       : err_set(err, "connection closed by peer in the middle of a %s packet", msg_type_name(c->type));
        if (n < 0)
            return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR
                       ? 0
                       : err_set(err, "receive failed: %s", strerror(errno));
        c->in_len += (size_t)n;
        c->bytes_in += (uint64_t)n;
        c->drained = (size_t)n < space;
    }
}

static int queue(Conn *c, const void *p, size_t n)
{
    if (n > c->out_cap - c->out_len) {
        /* drop what was sent before growing */
        if (c->out_sent) {
            memmove(c->out, c->out + c->out_sent, c->out_len - c->out_sent);
            c->out_len -= c->out_sent;
            c->out_sent = 0;
        }
        if (n > c->out_cap - c->out_len) {
            size_t cap = c->out_cap ? c->out_cap : 65536;
            while (cap - c->out_len < n)
                cap *= 2;
            uint8_t *q = realloc(c->out, cap);
            if (!q)
                return -1;
            c->out = q;
            c->out_cap = cap;
        }
    }
    memcpy(c->out + c->out_len, p, n);
    c->out_len += n;
    return 0;
}

int conn_send_msg(Conn *c, const MsgOut *m, size_t max_queue, Err *err)
{
    uint32_t type = m->type;
    const void *a = m->head, *b = m->tail;
    size_t alen = m->head_len, blen = m->tail_len;
    size_t total = PROTO_HEADER + alen + blen;
    if (total > msg_max_size(type))
        return err_set(err, "%s packet of %zu bytes exceeds the limit of %u", msg_type_name(type), total, msg_max_size(type));
    if (conn_pending(c) + total > max_queue)
        return err_set(err, "peer is not reading: %zu bytes already queued", conn_pending(c));
    uint32_t head[2] = {type, (uint32_t)total};
    if (queue(c, head, sizeof head) || (alen && queue(c, a, alen)) || (blen && queue(c, b, blen)))
        return err_set(err, "out of memory queueing a %s packet", msg_type_name(type));
    return 0;
}

long conn_flush(Conn *c, Err *err)
{
    while (c->out_sent < c->out_len) {
        ssize_t n = send(c->fd, c->out + c->out_sent, c->out_len - c->out_sent, MSG_NOSIGNAL);
        if (n < 0) {
            if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)
                break;
            return err_set(err, "send failed: %s", strerror(errno));
        }
        c->out_sent += (size_t)n;
        c->bytes_out += (uint64_t)n;
    }
    if (c->out_sent == c->out_len)
        c->out_sent = c->out_len = 0;
    return (long)conn_pending(c);
}

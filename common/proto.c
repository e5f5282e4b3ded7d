/* proto.c - see proto.h. */
#include "proto.h"

#include <errno.h>
#include <sodium.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

static const char *const names[PKT_TYPE_END] = {"?", "SERVER_HELLO", "HELLO", "WELCOME", "UPDATE", "COMPUTE", "DATA", "ASSET", "ERROR", "BYE"};

const char *proto_type_name(uint32_t type) { return type > 0 && type < PKT_TYPE_END ? names[type] : "unknown"; }

#define MIB (1024u * 1024u)

uint32_t proto_max_size(uint32_t type)
{
    switch (type) {
    case PKT_SERVER_HELLO: return PROTO_HEADER + 16 + PROTO_NONCE;
    case PKT_HELLO: return PROTO_HEADER + 20 + PROTO_NONCE + PROTO_PROOF;
    case PKT_WELCOME: return PROTO_HEADER + 4;
    case PKT_UPDATE: return 64 * MIB;
    case PKT_COMPUTE: return PROTO_HEADER + 12;
    case PKT_DATA: return PROTO_HEADER + 16 + 192 * MIB; /* a whole 8192x8192 frame */
    case PKT_ASSET: return 1024 * MIB;
    case PKT_ERROR: return PROTO_HEADER + PROTO_MAX_ERROR_TEXT;
    case PKT_BYE: return PROTO_HEADER;
    default: return 0;
    }
}

uint32_t proto_min_size(uint32_t type)
{
    switch (type) {
    case PKT_SERVER_HELLO:
    case PKT_HELLO:
    case PKT_WELCOME:
    case PKT_COMPUTE: return proto_max_size(type); /* fixed size */
    case PKT_UPDATE: return PROTO_HEADER + 16;
    case PKT_DATA: return PROTO_HEADER + 16;
    case PKT_ASSET: return PROTO_HEADER + 4 + PROTO_HASH;
    default: return PROTO_HEADER;
    }
}

void conn_init(Conn *c, int fd)
{
    memset(c, 0, sizeof *c);
    c->fd = fd;
}

void conn_close(Conn *c)
{
    if (c->fd >= 0)
        close(c->fd);
    free(c->body);
    free(c->out);
    memset(c, 0, sizeof *c);
    c->fd = -1;
}

int conn_read(Conn *c, Err *err)
{
    /* a packet handed out last time is finished: start the next one */
    if (c->head_got == PROTO_HEADER && c->body_got == c->body_size) {
        c->head_got = 0;
        c->body_got = c->body_size = 0;
    }
    for (;;) {
        if (c->head_got < PROTO_HEADER) {
            ssize_t n = recv(c->fd, c->head + c->head_got, PROTO_HEADER - c->head_got, 0);
            if (n == 0)
                return err_set(err, "connection closed by peer");
            if (n < 0)
                return errno == EAGAIN || errno == EWOULDBLOCK ? 0 : (errno == EINTR ? 0 : err_set(err, "receive failed: %s", strerror(errno)));
            c->head_got += (uint32_t)n;
            c->bytes_in += (uint64_t)n;
            if (c->head_got < PROTO_HEADER)
                continue;
            uint32_t size;
            memcpy(&c->type, c->head, 4);
            memcpy(&size, c->head + 4, 4);
            uint32_t max = proto_max_size(c->type);
            if (max == 0)
                return err_set(err, "packet of unknown type %u", c->type);
            if (size < proto_min_size(c->type) || size > max)
                return err_set(err, "%s packet claims %u bytes, allowed %u..%u", proto_type_name(c->type), size,
                               proto_min_size(c->type), max);
            c->body_size = size - PROTO_HEADER;
            c->body_got = 0;
            if (c->body_size > c->body_cap) {
                uint8_t *p = realloc(c->body, c->body_size);
                if (!p)
                    return err_set(err, "out of memory for a %u-byte packet", size);
                c->body = p;
                c->body_cap = c->body_size;
            }
        }
        if (c->body_got < c->body_size) {
            ssize_t n = recv(c->fd, c->body + c->body_got, c->body_size - c->body_got, 0);
            if (n == 0)
                return err_set(err, "connection closed by peer in the middle of a %s packet", proto_type_name(c->type));
            if (n < 0)
                return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? 0 : err_set(err, "receive failed: %s", strerror(errno));
            c->body_got += (uint32_t)n;
            c->bytes_in += (uint64_t)n;
        }
        if (c->body_got == c->body_size)
            return 1;
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

int conn_send2(Conn *c, uint32_t type, const void *a, size_t alen, const void *b, size_t blen, size_t max_queue, Err *err)
{
    size_t total = PROTO_HEADER + alen + blen;
    if (total > proto_max_size(type))
        return err_set(err, "%s packet of %zu bytes exceeds the limit of %u", proto_type_name(type), total, proto_max_size(type));
    if (conn_pending(c) + total > max_queue)
        return err_set(err, "peer is not reading: %zu bytes already queued", conn_pending(c));
    uint32_t head[2] = {type, (uint32_t)total};
    if (queue(c, head, sizeof head) || (alen && queue(c, a, alen)) || (blen && queue(c, b, blen)))
        return err_set(err, "out of memory queueing a %s packet", proto_type_name(type));
    return 0;
}

int conn_send(Conn *c, uint32_t type, const void *body, size_t len, size_t max_queue, Err *err)
{
    return conn_send2(c, type, body, len, NULL, 0, max_queue, err);
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

static void token_key(const char *token, uint8_t key[crypto_auth_hmacsha256_KEYBYTES])
{
    crypto_hash_sha256(key, (const unsigned char *)token, strlen(token));
}

void proto_proof(const char *token, const uint8_t sn[PROTO_NONCE], const uint8_t cn[PROTO_NONCE], uint8_t proof[PROTO_PROOF])
{
    static const char label[] = "lanray-auth-v1";
    uint8_t key[crypto_auth_hmacsha256_KEYBYTES], msg[sizeof label - 1 + 2 * PROTO_NONCE];
    token_key(token ? token : "", key);
    memcpy(msg, label, sizeof label - 1);
    memcpy(msg + sizeof label - 1, sn, PROTO_NONCE);
    memcpy(msg + sizeof label - 1 + PROTO_NONCE, cn, PROTO_NONCE);
    crypto_auth_hmacsha256(proof, msg, sizeof msg, key);
    sodium_memzero(key, sizeof key);
}

int proto_proof_ok(const char *token, const uint8_t sn[PROTO_NONCE], const uint8_t cn[PROTO_NONCE], const uint8_t proof[PROTO_PROOF])
{
    uint8_t want[PROTO_PROOF];
    proto_proof(token, sn, cn, want);
    return sodium_memcmp(want, proof, PROTO_PROOF) == 0;
}

void proto_random(void *buf, size_t len)
{
    if (sodium_init() < 0)
        abort(); /* no entropy source: nothing secure can be done */
    randombytes_buf(buf, len);
}

void proto_hash(const void *data, size_t len, uint8_t hash[PROTO_HASH]) { crypto_hash_sha256(hash, data, len); }

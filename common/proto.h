/* proto.h - lanray's network protocol: packet framing and connections.
 *
 * Every packet starts with an 8-byte header: u32 type, u32 total size
 * (header included), host byte order; docs/protocol.md lists the packets.
 * A Conn buffers one non-blocking socket: incoming bytes are cut into
 * packets only after the header's size has been checked against the limit
 * for its type, so a peer that lies about sizes cannot make us allocate. */
#ifndef LANRAY_PROTO_H
#define LANRAY_PROTO_H

#include <stddef.h>
#include <stdint.h>

#include "cursor.h"
#include "err.h"

#define PROTO_MAGIC 0x5941524cu /* "LRAY" */
#define PROTO_VERSION 3u
#define PROTO_BOM 0x01020304u
#define PROTO_HEADER 8u
#define PROTO_NONCE 32u
#define PROTO_PROOF 32u
#define PROTO_HASH 32u
#define PROTO_DEFAULT_PORT 7878
#define PROTO_MAX_ERROR_TEXT 1024u

typedef enum {
    PKT_SERVER_HELLO = 1, /* server -> client: magic, version, bom, flags, nonce */
    PKT_HELLO = 2,        /* client -> server: magic, version, bom, threads, real size, nonce, proof */
    PKT_WELCOME = 3,      /* server -> client: client id */
    PKT_UPDATE = 4,       /* server -> client: frame, size, up to 2 segments, serialised scene */
    PKT_COMPUTE = 5,      /* server -> client: frame, segment */
    PKT_DATA = 6,         /* client -> server: frame, segment, render time, RGB8 pixels */
    PKT_ASSET = 7,        /* server -> client: kind, content hash, payload */
    PKT_ERROR = 8,        /* either way: a reason, then the sender closes */
    PKT_BYE = 9,          /* either way: orderly goodbye */
    PKT_TYPE_END
} PacketType;

enum { ASSET_MODEL = 1, ASSET_TEXTURE = 2 };
enum { HELLO_TOKEN_REQUIRED = 1 };

/* A segment: pixels [first, first + count) of a frame, in row-major order. */
typedef struct {
    uint32_t first, count;
} Segment;

const char *proto_type_name(uint32_t type);
/* Largest and smallest total size accepted for a packet type (0 if unknown). */
uint32_t proto_max_size(uint32_t type);
uint32_t proto_min_size(uint32_t type);

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
/* Queues a packet (header added here); fails if the queue would exceed max_queue. */
int conn_send(Conn *c, uint32_t type, const void *body, size_t len, size_t max_queue, Err *err);
/* Two-part body (e.g. a fixed part and pixels) without an extra copy by the caller. */
int conn_send2(Conn *c, uint32_t type, const void *a, size_t alen, const void *b, size_t blen, size_t max_queue, Err *err);
/* Writes what the socket takes; returns bytes still queued, or -1 on error. */
long conn_flush(Conn *c, Err *err);
static inline size_t conn_pending(const Conn *c) { return c->out_len - c->out_sent; }

/* The authentication proof: HMAC-SHA256 keyed with SHA-256(token) over
 * "lanray-auth-v1" || server nonce || client nonce.  The token never travels. */
void proto_proof(const char *token, const uint8_t server_nonce[PROTO_NONCE], const uint8_t client_nonce[PROTO_NONCE],
                 uint8_t proof[PROTO_PROOF]);
int proto_proof_ok(const char *token, const uint8_t server_nonce[PROTO_NONCE], const uint8_t client_nonce[PROTO_NONCE],
                   const uint8_t proof[PROTO_PROOF]);
void proto_random(void *buf, size_t len);
void proto_hash(const void *data, size_t len, uint8_t hash[PROTO_HASH]);

#endif

/* msg.h - the packets' bodies: one struct per packet type and an
 * encode/decode pair for it, the only code that knows a layout.
 *
 * Every packet is an 8-byte header (u32 type, u32 total size, host byte
 * order; conn.h frames them) and a body laid out as below, all numbers
 * u32.  docs/protocol.md shows the same tables; tests/test_msg.c checks
 * them against msg_layout().  A body's big part (the scene, the
 * pixels, an asset's bytes, an error's text) is not copied: the encoder
 * points at it and the decoder points into the body it was given. */
#ifndef LANRAY_MSG_H
#define LANRAY_MSG_H

#include <stddef.h>
#include <stdint.h>

#include "base/err.h"
#include "render/segment.h"

#define PROTO_MAGIC 0x5941524cu /* "LRAY" */
#define PROTO_VERSION 33u /* 8: an UPDATE carries the frame's view apart, and the scene only when it changed;
                           * 9: the view's settings hold light_sampling (wire 6);
                           * 10: compressed pixels (HELLO codecs, WELCOME coding, DATA coding);
                           * 11: pipelined frames (UPDATE keep: the older frame still wanted);
                           * 12: the view's settings hold integrator (wire 7);
                           * 13: and emitter_sampling, roulette; materials a checker (wire 8);
                           * 14: and contrast (wire 9);
                           * 15: and light_samples (wire 10);
                           * 16: a texture ASSET's flags say each axis's wrap mode, its PNG
                           *     its alpha; materials a cutout (wire 11);
                           * 17: materials a normal map (wire 12);
                           * 18: materials an emission texture (wire 13);
                           * 19: materials a metal-roughness texture (wire 14);
                           * 20: materials an occlusion texture (wire 15);
                           * 21: materials a metal's rim colour, reflect_edge (wire 16);
                           * 22: materials a blending mask, mask_blend (wire 17);
                           * 23: the scene an environment (wire 18); a texture ASSET's
                           *     codec may be 3, a Radiance .hdr;
                           * 24: the view's settings hold denoise (wire 19), and with it a
                           *     DATA packet's pixels carry their guides (9 bytes each);
                           * 25: the view's settings hold batch (wire 20): a path-traced
                           *     still's batch of samples, whose DATA carries each
                           *     pixel's sums (reals);
                           * 26: the view's settings hold jitter (wire 21): a path-traced
                           *     moving frame's sample;
                           * 27: the view's settings hold guides (wire 22): a Whitted
                           *     moving frame's DATA carries each pixel's guide;
                           * 28: a guide 11 bytes: the instance its surface is of;
                           * 29: the view's settings hold clamp_indirect (wire 23);
                           * 30: and tonemap (wire 24);
                           * 31: and filter_glossy (wire 25);
                           * 32: and caustics (wire 26);
                           * 33: an ASSET a slice of its payload (total, offset); HAVE: a
                           *     client says it holds an asset decoded; a new scene's
                           *     assets are sent ahead of its frames */
#define PROTO_BOM 0x01020304u
#define PROTO_HEADER 8u
#define PROTO_NONCE 32u
#define PROTO_PROOF 32u
#define PROTO_HASH 32u
#define PROTO_DEFAULT_PORT 7878
#define PROTO_MAX_ERROR_TEXT 1024u
#define PROTO_MAX_PIXELS (256u << 20) /* a DATA packet's pixel bytes: a whole 8192x8192 frame of RGBE */
#define PROTO_ASSET_SLICE (256u << 10) /* an ASSET's bytes of the payload, at most */
#define PROTO_ASSET_MAX (1024u << 20)  /* an asset's payload, at most */

typedef enum {
    PKT_SERVER_HELLO = 1, /* server -> client: magic, version, bom, flags, nonce */
    PKT_HELLO = 2,        /* client -> server: magic, version, bom, threads, real size, codecs, nonce, proof */
    PKT_WELCOME = 3,      /* server -> client: client id, the pixels' coding */
    PKT_UPDATE = 4,       /* server -> client: frame, size, frames kept, scene id, up to 2 segments, the view, the scene if new */
    PKT_COMPUTE = 5,      /* server -> client: frame, segment */
    PKT_DATA = 6,         /* client -> server: frame, segment, render time, coding, RGB8 or RGBE pixels as coded */
    PKT_ASSET = 7,        /* server -> client: kind, content hash, payload */
    PKT_ERROR = 8,        /* either way: a reason, then the sender closes */
    PKT_BYE = 9,          /* either way: orderly goodbye */
    PKT_HAVE = 10,        /* client -> server: the hash of an asset it holds decoded */
    PKT_TYPE_END
} PacketType;

enum { ASSET_MODEL = 1, ASSET_TEXTURE = 2 };
enum { HELLO_TOKEN_REQUIRED = 1 };

typedef struct {
    uint32_t magic, version, bom, flags; /* flags: HELLO_TOKEN_REQUIRED */
    uint8_t nonce[PROTO_NONCE];
} MsgServerHello;

typedef struct {
    uint32_t magic, version, bom, threads, real_size;
    uint32_t codecs; /* the codecs the client codes pixels with, 1 << PIX_* (net/pixcodec.h) */
    uint8_t nonce[PROTO_NONCE], proof[PROTO_PROOF];
} MsgHello;

typedef struct {
    uint32_t id;
    uint32_t coding; /* how the client is to code its DATA: one of its codecs, with PIX_PREDICT or not */
} MsgWelcome;

/* A frame: its view (wire_encode_view: the camera and the settings), and
 * the scene description (wire_encode_scene) numbered scene_id, sent only
 * to a client that does not hold that description yet (scene_len 0 then).
 * The view and the scene are one block in the packet: encoding sends
 * view_len + scene_len bytes from `view`; decoding points view and scene
 * into the body. */
typedef struct {
    uint32_t frame, width, height;
    uint32_t keep;      /* the oldest frame whose segments the client still renders: frame, or the one before it
                         * where the server started this frame before that one was finished (pipelined) */
    uint32_t scene_id;  /* the description's number (the server counts up from 1 as it changes) */
    uint32_t view_len;
    uint32_t nseg;      /* <= 2 */
    Segment seg[2];
    const uint8_t *view;
    const uint8_t *scene;
    size_t scene_len;
} MsgUpdate;

typedef struct {
    uint32_t frame;
    Segment seg;
} MsgCompute;

typedef struct {
    uint32_t frame;
    Segment seg;
    uint32_t render_us;
    uint32_t coding;       /* PIX_RAW, or the WELCOME's coding (pixcodec.h) */
    const uint8_t *pixels; /* len bytes: bpp * seg.count raw, fewer coded */
    size_t len;
    uint32_t bpp;          /* not sent: 3 (RGB8), or 4 (RGBE) where the frame's scene says hdr */
} MsgData;

/* A slice of an asset: its payload's bytes from offset on (len of them,
 * PROTO_ASSET_SLICE at most), of a payload of total bytes
 * (PROTO_ASSET_MAX at most).  An asset travels as its slices in order, one
 * asset after another, so that the frames' packets pass between them. */
typedef struct {
    uint32_t kind; /* ASSET_MODEL or ASSET_TEXTURE */
    uint8_t hash[PROTO_HASH];
    uint32_t total, offset;
    const uint8_t *data;
    size_t len;
} MsgAsset;

/* A client's word that it holds the asset of that hash decoded, ready
 * for a scene that names it (one for each ASSET, in its order). */
typedef struct {
    uint8_t hash[PROTO_HASH];
} MsgHave;

typedef struct {
    const char *text; /* encoding: up to PROTO_MAX_ERROR_TEXT bytes of it are sent */
    size_t len;
} MsgError;

/* A packet ready to queue: its type, the fixed part encoded, and the big
 * part it points at (conn.h's conn_send_msg sends both). */
#define MSG_HEAD_MAX 96u
typedef struct {
    uint32_t type;
    uint8_t head[MSG_HEAD_MAX];
    size_t head_len;
    const void *tail;
    size_t tail_len;
} MsgOut;

void msg_encode_server_hello(const MsgServerHello *m, MsgOut *out);
void msg_encode_hello(const MsgHello *m, MsgOut *out);
void msg_encode_welcome(const MsgWelcome *m, MsgOut *out);
void msg_encode_update(const MsgUpdate *m, MsgOut *out);
void msg_encode_compute(const MsgCompute *m, MsgOut *out);
void msg_encode_data(const MsgData *m, MsgOut *out);
void msg_encode_asset(const MsgAsset *m, MsgOut *out);
void msg_encode_error(const MsgError *m, MsgOut *out);
void msg_encode_bye(MsgOut *out);
void msg_encode_have(const MsgHave *m, MsgOut *out);

/* Decoders take a body (without the header) and check its size against
 * the layout: -1 with the packet named in err when it does not fit.  What
 * the fields mean (a version, a segment inside the frame) is the caller's
 * to check. */
int msg_decode_server_hello(const uint8_t *body, size_t len, MsgServerHello *m, Err *err);
int msg_decode_hello(const uint8_t *body, size_t len, MsgHello *m, Err *err);
int msg_decode_welcome(const uint8_t *body, size_t len, MsgWelcome *m, Err *err);
int msg_decode_update(const uint8_t *body, size_t len, MsgUpdate *m, Err *err);
int msg_decode_compute(const uint8_t *body, size_t len, MsgCompute *m, Err *err);
/* A DATA packet's pixel size is the frame's (render_pixel_bytes), which
 * the receiver knows from the view it sent: bpp.  Raw pixels must be the
 * segment's bytes exactly, coded ones fewer (pixcodec_decode then checks
 * that they decode to exactly the segment).  bpp 0: not checked (a frame
 * the receiver no longer holds, whose pixels it drops unread). */
int msg_decode_data(const uint8_t *body, size_t len, uint32_t bpp, MsgData *m, Err *err);
/* An ASSET's slice must lie within its total, and the total within
 * PROTO_ASSET_MAX. */
int msg_decode_asset(const uint8_t *body, size_t len, MsgAsset *m, Err *err);
int msg_decode_have(const uint8_t *body, size_t len, MsgHave *m, Err *err);
/* The text made printable (other bytes become '?') and NUL-terminated. */
int msg_decode_error(const uint8_t *body, size_t len, char text[PROTO_MAX_ERROR_TEXT + 1], Err *err);

const char *msg_type_name(uint32_t type);
/* Largest and smallest total size (header included) of a packet type; 0 if unknown. */
uint32_t msg_max_size(uint32_t type);
uint32_t msg_min_size(uint32_t type);

/* The layouts as text, one line per field: "TYPE OFFSET SIZE NAME" (SIZE
 * "rest" for the rest of the body, "8*nseg" for an UPDATE's segments);
 * docs/protocol.md is checked against it. */
void msg_layout(void (*line)(void *ctx, const char *text), void *ctx);

#endif

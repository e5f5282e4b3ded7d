/* msg.c - see msg.h.  Each packet's fixed part is a table of fields (name,
 * where it sits in the struct, its size); encoding, decoding and the
 * layout that docs/protocol.md is checked against all walk the same table,
 * so a layout is written once. */
#include "net/msg.h"

#include <stddef.h>
#include <stdio.h>
#include <string.h>

#define MIB (1024u * 1024u)

typedef struct {
    const char *name;
    size_t off;    /* in the struct */
    uint32_t size; /* 4: a u32; else that many bytes */
} Field;

/* The segments of an UPDATE: MsgUpdate.nseg of them (a field before
 * them), each u32 first, u32 count. */
#define SEGMENTS_BY_NSEG UINT32_MAX

typedef struct {
    const char *name;
    const Field *fields;   /* the fixed part, in order; ends with a NULL name */
    const char *tail;      /* the rest of the body, or NULL */
    uint32_t max_size;     /* total, header included; 0: the fixed part's */
} Layout;

static const Field server_hello_f[] = {
    {"magic", offsetof(MsgServerHello, magic), 4},   {"version", offsetof(MsgServerHello, version), 4},
    {"bom", offsetof(MsgServerHello, bom), 4},       {"flags", offsetof(MsgServerHello, flags), 4},
    {"nonce", offsetof(MsgServerHello, nonce), PROTO_NONCE}, {NULL, 0, 0}};
static const Field hello_f[] = {
    {"magic", offsetof(MsgHello, magic), 4},         {"version", offsetof(MsgHello, version), 4},
    {"bom", offsetof(MsgHello, bom), 4},             {"threads", offsetof(MsgHello, threads), 4},
    {"real_size", offsetof(MsgHello, real_size), 4}, {"codecs", offsetof(MsgHello, codecs), 4},
    {"nonce", offsetof(MsgHello, nonce), PROTO_NONCE},
    {"proof", offsetof(MsgHello, proof), PROTO_PROOF}, {NULL, 0, 0}};
static const Field welcome_f[] = {{"id", offsetof(MsgWelcome, id), 4}, {"coding", offsetof(MsgWelcome, coding), 4},
                                  {NULL, 0, 0}};
static const Field update_f[] = {
    {"frame", offsetof(MsgUpdate, frame), 4},         {"width", offsetof(MsgUpdate, width), 4},
    {"height", offsetof(MsgUpdate, height), 4},       {"keep", offsetof(MsgUpdate, keep), 4},
    {"scene_id", offsetof(MsgUpdate, scene_id), 4},
    {"view_len", offsetof(MsgUpdate, view_len), 4},   {"nseg", offsetof(MsgUpdate, nseg), 4},
    {"segments", offsetof(MsgUpdate, seg), SEGMENTS_BY_NSEG}, {NULL, 0, 0}};
static const Field compute_f[] = {{"frame", offsetof(MsgCompute, frame), 4},
                                  {"first", offsetof(MsgCompute, seg.first), 4},
                                  {"count", offsetof(MsgCompute, seg.count), 4},
                                  {NULL, 0, 0}};
static const Field data_f[] = {{"frame", offsetof(MsgData, frame), 4},
                               {"first", offsetof(MsgData, seg.first), 4},
                               {"count", offsetof(MsgData, seg.count), 4},
                               {"render_us", offsetof(MsgData, render_us), 4},
                               {"coding", offsetof(MsgData, coding), 4},
                               {NULL, 0, 0}};
static const Field asset_f[] = {{"kind", offsetof(MsgAsset, kind), 4}, {"hash", offsetof(MsgAsset, hash), PROTO_HASH},
                                {"total", offsetof(MsgAsset, total), 4}, {"offset", offsetof(MsgAsset, offset), 4},
                                {NULL, 0, 0}};
static const Field have_f[] = {{"hash", offsetof(MsgHave, hash), PROTO_HASH}, {NULL, 0, 0}};
static const Field none_f[] = {{NULL, 0, 0}};

static const Layout layouts[PKT_TYPE_END] = {
    [PKT_SERVER_HELLO] = {"SERVER_HELLO", server_hello_f, NULL, 0},
    [PKT_HELLO] = {"HELLO", hello_f, NULL, 0},
    [PKT_WELCOME] = {"WELCOME", welcome_f, NULL, 0},
    [PKT_UPDATE] = {"UPDATE", update_f, "view+scene", 64 * MIB},
    [PKT_COMPUTE] = {"COMPUTE", compute_f, NULL, 0},
    [PKT_DATA] = {"DATA", data_f, "pixels", PROTO_HEADER + 20 + PROTO_MAX_PIXELS},
    [PKT_ASSET] = {"ASSET", asset_f, "slice", PROTO_HEADER + 44 + PROTO_ASSET_SLICE},
    [PKT_ERROR] = {"ERROR", none_f, "text", PROTO_HEADER + PROTO_MAX_ERROR_TEXT},
    [PKT_BYE] = {"BYE", none_f, NULL, 0},
    [PKT_HAVE] = {"HAVE", have_f, NULL, 0},
};

static const Layout *layout_of(uint32_t type) { return type > 0 && type < PKT_TYPE_END ? &layouts[type] : NULL; }

/* Bytes of the fixed part, with nseg segments where the layout has them. */
static uint32_t fixed_size(const Layout *l, uint32_t nseg)
{
    uint32_t n = 0;
    for (const Field *f = l->fields; f->name; f++)
        n += f->size == SEGMENTS_BY_NSEG ? 8 * nseg : f->size;
    return n;
}

const char *msg_type_name(uint32_t type) { return layout_of(type) ? layout_of(type)->name : "unknown"; }

uint32_t msg_max_size(uint32_t type)
{
    const Layout *l = layout_of(type);
    if (!l)
        return 0;
    return l->max_size ? l->max_size : PROTO_HEADER + fixed_size(l, 2);
}

uint32_t msg_min_size(uint32_t type)
{
    const Layout *l = layout_of(type);
    return l ? PROTO_HEADER + fixed_size(l, 0) : 0;
}

/* The fixed part of the struct at m into out->head; the tail pointed at. */
static void encode(uint32_t type, const void *m, const void *tail, size_t tail_len, MsgOut *out)
{
    const Layout *l = &layouts[type];
    const uint8_t *s = m;
    out->type = type;
    out->head_len = 0;
    for (const Field *f = l->fields; f->name; f++) {
        uint32_t n = f->size;
        if (n == SEGMENTS_BY_NSEG) {
            memcpy(&n, s + offsetof(MsgUpdate, nseg), 4);
            n = 8 * (n < 2 ? n : 2);
        }
        memcpy(out->head + out->head_len, s + f->off, n);
        out->head_len += n;
    }
    out->tail = tail;
    out->tail_len = tail_len;
}

/* The fixed part of body into the struct at m; the tail's start and length.
 * The body must hold the fixed part, and nothing more where the layout
 * has no tail. */
static int decode(uint32_t type, const uint8_t *body, size_t len, void *m, const uint8_t **tail, size_t *tail_len,
                  Err *err)
{
    const Layout *l = &layouts[type];
    uint8_t *s = m;
    size_t at = 0;
    for (const Field *f = l->fields; f->name; f++) {
        size_t n = f->size;
        if (n == SEGMENTS_BY_NSEG) {
            uint32_t nseg;
            memcpy(&nseg, s + offsetof(MsgUpdate, nseg), 4);
            if (nseg > 2)
                return err_set(err, "%s packet with %u segments (2 at most)", l->name, nseg);
            n = 8 * (size_t)nseg;
        }
        if (n > len - at)
            return err_set(err, "%s packet of %zu bytes is too short for its %s", l->name, len, f->name);
        memcpy(s + f->off, body + at, n);
        at += n;
    }
    if (!l->tail && at != len)
        return err_set(err, "%s packet of %zu bytes, its layout has %zu", l->name, len, at);
    if (tail) {
        *tail = len ? body + at : NULL; /* an empty body may come as NULL: no offset on it */
        *tail_len = len - at;
    }
    return 0;
}

void msg_encode_server_hello(const MsgServerHello *m, MsgOut *out) { encode(PKT_SERVER_HELLO, m, NULL, 0, out); }
void msg_encode_hello(const MsgHello *m, MsgOut *out) { encode(PKT_HELLO, m, NULL, 0, out); }
void msg_encode_welcome(const MsgWelcome *m, MsgOut *out) { encode(PKT_WELCOME, m, NULL, 0, out); }
void msg_encode_update(const MsgUpdate *m, MsgOut *out)
{
    encode(PKT_UPDATE, m, m->view, (size_t)m->view_len + m->scene_len, out);
}
void msg_encode_compute(const MsgCompute *m, MsgOut *out) { encode(PKT_COMPUTE, m, NULL, 0, out); }
void msg_encode_data(const MsgData *m, MsgOut *out)
{
    encode(PKT_DATA, m, m->pixels, m->len, out);
}
void msg_encode_asset(const MsgAsset *m, MsgOut *out) { encode(PKT_ASSET, m, m->data, m->len, out); }
void msg_encode_error(const MsgError *m, MsgOut *out)
{
    encode(PKT_ERROR, m, m->text, m->len < PROTO_MAX_ERROR_TEXT ? m->len : PROTO_MAX_ERROR_TEXT, out);
}
void msg_encode_bye(MsgOut *out) { encode(PKT_BYE, NULL, NULL, 0, out); }
void msg_encode_have(const MsgHave *m, MsgOut *out) { encode(PKT_HAVE, m, NULL, 0, out); }

int msg_decode_server_hello(const uint8_t *body, size_t len, MsgServerHello *m, Err *err)
{
    return decode(PKT_SERVER_HELLO, body, len, m, NULL, NULL, err);
}

int msg_decode_hello(const uint8_t *body, size_t len, MsgHello *m, Err *err)
{
    return decode(PKT_HELLO, body, len, m, NULL, NULL, err);
}

int msg_decode_welcome(const uint8_t *body, size_t len, MsgWelcome *m, Err *err)
{
    return decode(PKT_WELCOME, body, len, m, NULL, NULL, err);
}

int msg_decode_update(const uint8_t *body, size_t len, MsgUpdate *m, Err *err)
{
    memset(m, 0, sizeof *m);
    size_t rest;
    if (decode(PKT_UPDATE, body, len, m, &m->view, &rest, err))
        return -1;
    if (m->view_len > rest)
        return err_set(err, "UPDATE packet with a view of %u bytes and %zu bytes left", m->view_len, rest);
    m->scene = m->view ? m->view + m->view_len : NULL;
    m->scene_len = rest - m->view_len;
    return 0;
}

int msg_decode_compute(const uint8_t *body, size_t len, MsgCompute *m, Err *err)
{
    return decode(PKT_COMPUTE, body, len, m, NULL, NULL, err);
}

int msg_decode_data(const uint8_t *body, size_t len, uint32_t bpp, MsgData *m, Err *err)
{
    if (decode(PKT_DATA, body, len, m, &m->pixels, &m->len, err))
        return -1;
    m->bpp = bpp;
    const uint64_t raw = bpp * (uint64_t)m->seg.count;
    if (bpp && (m->coding == 0 ? m->len != raw : m->len >= raw))
        return err_set(err, "DATA packet of %zu %s pixel bytes for a segment of %u pixels of %u bytes", m->len,
                       m->coding == 0 ? "raw" : "coded", m->seg.count, bpp);
    return 0;
}

int msg_decode_asset(const uint8_t *body, size_t len, MsgAsset *m, Err *err)
{
    if (decode(PKT_ASSET, body, len, m, &m->data, &m->len, err))
        return -1;
    if (m->total > PROTO_ASSET_MAX)
        return err_set(err, "ASSET of %u bytes (%u at most)", m->total, PROTO_ASSET_MAX);
    if (m->offset > m->total || m->len > m->total - m->offset)
        return err_set(err, "ASSET slice of %zu bytes at %u of an asset of %u bytes", m->len, m->offset, m->total);
    return 0;
}

int msg_decode_have(const uint8_t *body, size_t len, MsgHave *m, Err *err)
{
    return decode(PKT_HAVE, body, len, m, NULL, NULL, err);
}

int msg_decode_error(const uint8_t *body, size_t len, char text[PROTO_MAX_ERROR_TEXT + 1], Err *err)
{
    const uint8_t *t;
    size_t n;
    if (decode(PKT_ERROR, body, len, NULL, &t, &n, err))
        return -1;
    if (n > PROTO_MAX_ERROR_TEXT)
        n = PROTO_MAX_ERROR_TEXT;
    for (size_t i = 0; i < n; i++)
        text[i] = t[i] >= 32 && t[i] <= 126 ? (char)t[i] : '?';
    text[n] = 0;
    return 0;
}

void msg_layout(void (*line)(void *ctx, const char *text), void *ctx)
{
    char buf[160];
    for (uint32_t type = 1; type < PKT_TYPE_END; type++) {
        const Layout *l = &layouts[type];
        uint32_t at = 0;
        const char *plus = ""; /* after the segments, offsets grow by them */
        for (const Field *f = l->fields; f->name; f++) {
            if (f->size == SEGMENTS_BY_NSEG) {
                snprintf(buf, sizeof buf, "%s %u 8*nseg %s", l->name, at, f->name);
                plus = "+8*nseg";
            } else {
                snprintf(buf, sizeof buf, "%s %u%s %u %s", l->name, at, plus, f->size, f->name);
                at += f->size;
            }
            line(ctx, buf);
        }
        if (l->tail) {
            snprintf(buf, sizeof buf, "%s %u%s rest %s", l->name, at, plus, l->tail);
            line(ctx, buf);
        }
    }
}

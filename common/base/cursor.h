/* cursor.h - bounds-checked reading and growable writing of binary data.
 *
 * The binary parsers of outside bytes (.tmd files, serialised scenes,
 * texture assets, the importer's answer) read through a Cursor; packet
 * bodies go through msg.c's field tables.  Each get checks the bytes left first, and
 * after the first failure every further get fails too, so a parser may read a
 * whole record and test `cur.failed` once.  Values are in host byte order;
 * the formats carry a byte-order mark to detect foreign files. */
#ifndef LANRAY_CURSOR_H
#define LANRAY_CURSOR_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct {
    const uint8_t *p;
    size_t left;
    int failed;
} Cursor;

static inline Cursor cursor_make(const void *data, size_t len)
{
    Cursor c = {data, len, 0};
    return c;
}

/* Copies n bytes out, or fails without reading anything. */
static inline int cursor_get(Cursor *c, void *dst, size_t n)
{
    if (c->failed || n > c->left) {
        c->failed = 1;
        return -1;
    }
    memcpy(dst, c->p, n);
    c->p += n;
    c->left -= n;
    return 0;
}

static inline uint32_t cursor_u32(Cursor *c)
{
    uint32_t v = 0;
    cursor_get(c, &v, sizeof v);
    return v;
}

static inline float cursor_f32(Cursor *c)
{
    float v = 0;
    cursor_get(c, &v, sizeof v);
    return v;
}

/* n <= 4 bytes as a little-endian number (the image formats' order, not
 * the host's). */
static inline uint32_t bytes_le(const uint8_t *b, int n)
{
    uint32_t v = 0;
    for (int i = n - 1; i >= 0; i--)
        v = v << 8 | b[i];
    return v;
}

/* A byte sink that grows; `failed` is set on out-of-memory and sticks. */
typedef struct {
    uint8_t *data;
    size_t len, cap;
    int failed;
} Sink;

int sink_put(Sink *s, const void *src, size_t n);
static inline int sink_u32(Sink *s, uint32_t v) { return sink_put(s, &v, sizeof v); }
static inline int sink_f32(Sink *s, float v) { return sink_put(s, &v, sizeof v); }
void sink_free(Sink *s);

#endif

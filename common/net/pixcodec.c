/* pixcodec.c - see pixcodec.h. */
#include "net/pixcodec.h"

#include <lz4.h>
#include <stdlib.h>
#include <string.h>
#include <zstd.h>

/* LZ4 is the coding for a server whose CPU, not its link, is the limit
 * (many clients on a fast LAN): a faster setting makes fewer, longer
 * matches, which the server decodes faster, for a few more bytes
 * (docs/scaling.md: 2-line segments of the default scene). */
#define PIX_LZ4_ACCELERATION 4

struct PixCodec {
    ZSTD_CCtx *zc;
    ZSTD_DCtx *zd;
    uint8_t *scratch; /* the predicted bytes before coding */
    size_t cap;
};

PixCodec *pixcodec_create(void)
{
    PixCodec *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->zc = ZSTD_createCCtx();
    c->zd = ZSTD_createDCtx();
    if (!c->zc || !c->zd || ZSTD_isError(ZSTD_CCtx_setParameter(c->zc, ZSTD_c_compressionLevel, 1)) ||
        ZSTD_isError(ZSTD_CCtx_setParameter(c->zc, ZSTD_c_checksumFlag, 0)) ||
        ZSTD_isError(ZSTD_CCtx_setParameter(c->zc, ZSTD_c_contentSizeFlag, 1))) {
        pixcodec_destroy(c);
        return NULL;
    }
    return c;
}

void pixcodec_destroy(PixCodec *c)
{
    if (!c)
        return;
    ZSTD_freeCCtx(c->zc);
    ZSTD_freeDCtx(c->zd);
    free(c->scratch);
    free(c);
}

size_t pixcodec_bound(size_t n)
{
    size_t z = ZSTD_compressBound(n), l = n <= LZ4_MAX_INPUT_SIZE ? (size_t)LZ4_compressBound((int)n) : 0;
    size_t b = z > l ? z : l;
    return b > n ? b : n;
}

static int reserve(PixCodec *c, size_t n, Err *err)
{
    if (n <= c->cap)
        return 0;
    uint8_t *p = realloc(c->scratch, n);
    if (!p)
        return err_set(err, "pixels: out of memory for %zu bytes", n);
    c->scratch = p;
    c->cap = n;
    return 0;
}

/* Each byte minus the same channel of the pixel before it (the first
 * pixel as it is), and back: smooth runs of a rendered line become small
 * numbers that repeat.  The pixel before is kept in locals: through memory
 * each byte waited on the store of the one bpp before it (decoding a
 * 2-line segment took 4 us more than zstd alone). */
static void predict(const uint8_t *px, size_t n, uint32_t bpp, uint8_t *out)
{
    size_t head = n < bpp ? n : bpp;
    memcpy(out, px, head);
    for (size_t i = bpp; i < n; i++)
        out[i] = (uint8_t)(px[i] - px[i - bpp]);
}

static void unpredict(uint8_t *px, size_t n, uint32_t bpp)
{
    if (n < bpp)
        return;
    uint8_t a = px[0], b = px[1], c = px[2], d = bpp == 4 ? px[3] : 0;
    size_t i = bpp;
    if (bpp == 3) {
        for (; i + 3 <= n; i += 3) {
            a = (uint8_t)(a + px[i]), b = (uint8_t)(b + px[i + 1]), c = (uint8_t)(c + px[i + 2]);
            px[i] = a, px[i + 1] = b, px[i + 2] = c;
        }
    } else if (bpp == 4) {
        for (; i + 4 <= n; i += 4) {
            a = (uint8_t)(a + px[i]), b = (uint8_t)(b + px[i + 1]), c = (uint8_t)(c + px[i + 2]), d = (uint8_t)(d + px[i + 3]);
            px[i] = a, px[i + 1] = b, px[i + 2] = c, px[i + 3] = d;
        }
    }
    /* a pixel with its guide (settings denoise: 14 or 15 bytes) byte by
     * byte; a partial pixel at the end (never in a DATA packet) */
    for (; i < n; i++)
        px[i] = (uint8_t)(px[i] + px[i - bpp]);
}

int pixcodec_encode(PixCodec *c, uint32_t coding, const uint8_t *px, size_t n, uint32_t bpp, uint8_t *out,
                    size_t *out_len, Err *err)
{
    const uint32_t codec = coding & ~(uint32_t)PIX_PREDICT;
    const uint8_t *src = px;
    if (n == 0) { /* an empty segment (a hostile server's WORK): no bytes, and no scratch to predict into */
        *out_len = 0;
        return PIX_RAW;
    }
    if (codec != PIX_RAW && (coding & PIX_PREDICT)) {
        if (reserve(c, n, err))
            return -1;
        predict(px, n, bpp, c->scratch);
        src = c->scratch;
    }
    size_t got = 0;
    const size_t cap = pixcodec_bound(n);
    if (codec == PIX_ZSTD) {
        size_t r = ZSTD_compress2(c->zc, out, cap, src, n);
        got = ZSTD_isError(r) ? 0 : r;
    } else if (codec == PIX_LZ4 && n <= LZ4_MAX_INPUT_SIZE) {
        int r = LZ4_compress_fast((const char *)src, (char *)out, (int)n, (int)(cap > INT32_MAX ? INT32_MAX : cap),
                                  PIX_LZ4_ACCELERATION);
        got = r > 0 ? (size_t)r : 0;
    }
    if (got == 0 || got >= n) { /* nothing saved (or no such codec): the bytes as they are */
        memcpy(out, px, n);
        *out_len = n;
        return PIX_RAW;
    }
    *out_len = got;
    return (int)coding;
}

int pixcodec_known(uint32_t coding)
{
    return (coding & ~(uint32_t)PIX_PREDICT) < PIX_CODECS && coding != (PIX_RAW | PIX_PREDICT);
}

int pixcodec_decode(PixCodec *c, uint32_t coding, const uint8_t *in, size_t len, uint8_t *dst, size_t n, uint32_t bpp,
                    Err *err)
{
    const uint32_t codec = coding & ~(uint32_t)PIX_PREDICT;
    if (!pixcodec_known(coding))
        return err_set(err, "pixels: unknown coding %#x", coding);
    if (codec != PIX_RAW && len >= n)
        return err_set(err, "pixels: %zu coded bytes for %zu raw ones (a coded segment is smaller than its pixels)", len,
                       n);
    if (codec == PIX_RAW) {
        if (len != n)
            return err_set(err, "pixels: %zu bytes for a segment of %zu", len, n);
        memcpy(dst, in, n);
        return 0;
    }
    if (codec == PIX_ZSTD) {
        /* the frame must say its size, and say exactly n, before a byte is written */
        unsigned long long said = ZSTD_getFrameContentSize(in, len);
        if (said != (unsigned long long)n)
            return err_set(err, "pixels: a zstd frame of %s bytes for a segment of %zu",
                           said == ZSTD_CONTENTSIZE_UNKNOWN ? "unknown" : said == ZSTD_CONTENTSIZE_ERROR ? "bad" : "other",
                           n);
        size_t r = ZSTD_decompressDCtx(c->zd, dst, n, in, len);
        if (ZSTD_isError(r) || r != n)
            return err_set(err, "pixels: zstd: %s", ZSTD_isError(r) ? ZSTD_getErrorName(r) : "short");
    } else {
        if (n > LZ4_MAX_INPUT_SIZE)
            return err_set(err, "pixels: a segment of %zu bytes is too large for lz4", n);
        /* the safe decoder never writes past n; it must fill all n */
        int r = LZ4_decompress_safe((const char *)in, (char *)dst, (int)len, (int)n);
        if (r != (int)n)
            return err_set(err, "pixels: lz4 data that %s", r < 0 ? "does not decode" : "decodes short of the segment");
    }
    if (coding & PIX_PREDICT)
        unpredict(dst, n, bpp);
    return 0;
}

const char *pixcodec_name(uint32_t coding)
{
    static const char *const names[] = {"raw", "zstd", "lz4", "raw+predict", "zstd+predict", "lz4+predict"};
    const uint32_t codec = coding & ~(uint32_t)PIX_PREDICT;
    if (codec >= PIX_CODECS)
        return "unknown";
    return names[codec + (coding & PIX_PREDICT ? 3 : 0)];
}

/* fuzz_pixels.c - a DATA packet's coded pixels (pixcodec_decode) on
 * arbitrary bytes: the first 4 bytes are the coding, the next 2 the
 * segment's pixel count (1..4096), the next 1 its pixel size (3 or 4), the
 * rest the coded bytes.  Whatever it decodes must stay inside the segment
 * (ASan guards the buffer's end), and a segment coded by the encoder
 * must come back the same. */
#include <assert.h>
#include <string.h>

#include "fuzz.h"
#include "net/pixcodec.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static PixCodec *c;
    if (!c && !(c = pixcodec_create()))
        return 0;
    if (size < 7)
        return 0;
    uint32_t coding;
    uint16_t count;
    memcpy(&coding, data, 4);
    memcpy(&count, data + 4, 2);
    const uint32_t bpp = data[6] & 1 ? 4 : 3;
    const size_t n = (size_t)(count % 4096 + 1) * bpp;
    uint8_t *dst = malloc(n); /* exactly the segment: a byte past it is an ASan report */
    if (!dst)
        return 0;
    Err err;
    pixcodec_decode(c, coding, data + 7, size - 7, dst, n, bpp, &err);
    /* the rest, taken as pixels, through the encoder and back */
    const size_t m = (size - 7) / bpp * bpp;
    uint8_t *coded = malloc(pixcodec_bound(m) + 1), *back = malloc(m + 1);
    if (coded && back && m) {
        size_t len;
        int used = pixcodec_encode(c, coding & (PIX_PREDICT | 3u), data + 7, m, bpp, coded, &len, &err);
        if (used >= 0) {
            assert(pixcodec_decode(c, (uint32_t)used, coded, len, back, m, bpp, &err) == 0);
            assert(memcmp(back, data + 7, m) == 0);
        }
    }
    free(coded);
    free(back);
    free(dst);
    return 0;
}

/* fuzz_pixels.c - a DATA packet's coded pixels (pixcodec_decode) on
 * arbitrary bytes: the first 4 bytes are the coding, the next 2 the
 * segment's pixel count (1..4096), the next 1 its pixel size (bit 0: 3 or
 * 4 bytes of colour; bit 1: a denoised scene's, each pixel's guide after
 * them), the rest the coded bytes.  Whatever it decodes must stay inside
 * the segment (ASan guards the buffer's end), and a segment coded by the
 * encoder must come back the same.  A guided segment, decoded, is then
 * filtered as a frame (its width from the size byte's other bits) by the
 * denoiser, as a server filters what clients send (render/denoise.h). */
#include <assert.h>
#include <string.h>

#include "fuzz.h"
#include "net/pixcodec.h"
#include "render/denoise.h"

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
    const uint32_t cb = data[6] & 1 ? 4 : 3, guided = (data[6] >> 1) & 1;
    const uint32_t bpp = cb + (guided ? DENOISE_GUIDE_BYTES : 0), pixels = count % 4096 + 1;
    const size_t n = (size_t)pixels * bpp;
    uint8_t *dst = malloc(n); /* exactly the segment: a byte past it is an ASan report */
    if (!dst)
        return 0;
    Err err;
    if (pixcodec_decode(c, coding, data + 7, size - 7, dst, n, bpp, &err) == 0 && guided) {
        const uint32_t w = (uint32_t)(data[6] >> 2) % 64 + 1, h = (pixels + w - 1) / w;
        uint8_t *frame = calloc((size_t)w * h, bpp), *out = malloc((size_t)w * h * cb);
        Denoiser *d = denoiser_create(NULL, w, h);
        if (frame && out && d) {
            memcpy(frame, dst, n);
            assert(denoise_frame(d, frame, w, h, cb, data[5] & 1, out, &err) == 0);
        }
        denoiser_destroy(d);
        free(frame);
        free(out);
    }
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

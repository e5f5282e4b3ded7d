/* codec_bench.c - what compressing a DATA packet's pixels buys, measured
 * on rendered segments (not whole frames: a packet carries a segment).
 *
 *     codec_bench [SCENE] [--width W] [--height H] [--rounds N]
 *
 * Renders the scene (no scene: the default one) at one sample a pixel, as
 * 8-bit sRGB and as RGBE (--hdr), cuts each frame into segments of 1, 2,
 * 16 lines and the whole frame, and codes every segment with each coding
 * (raw, zstd level 1, LZ4, each with and without the left-neighbour
 * predictor): bytes against raw, and the microseconds a segment takes to
 * code and to decode (best of N rounds), side by side in one run.  Each
 * decoded segment is checked against the rendered one.  Timing only: it
 * fails only where a segment does not come back the same. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/timer.h"
#include "net/pixcodec.h"
#include "render/render.h"
#include "scene/scene_default.h"
#include "scene/scene_parse.h"

static const uint32_t codings[] = {PIX_RAW, PIX_ZSTD, PIX_LZ4, PIX_ZSTD | PIX_PREDICT, PIX_LZ4 | PIX_PREDICT};
#define NCODINGS (int)(sizeof codings / sizeof *codings)

/* One frame's segments of `lines` lines coded with each coding: prints a row each. */
static int bench_segments(PixCodec *pc, const uint8_t *px, int w, int h, uint32_t bpp, int lines, int rounds)
{
    const size_t seg_bytes = (size_t)w * (size_t)lines * bpp, total = (size_t)w * (size_t)h * bpp;
    uint8_t *out = malloc(pixcodec_bound(seg_bytes)), *back = malloc(seg_bytes);
    if (!out || !back)
        return fprintf(stderr, "codec_bench: out of memory\n"), free(out), free(back), 1;
    for (int c = 0; c < NCODINGS; c++) {
        double best_enc = 1e30, best_dec = 1e30;
        size_t coded = 0, segs = 0, raw_kept = 0;
        for (int r = 0; r < rounds; r++) {
            double enc = 0, dec = 0;
            coded = segs = raw_kept = 0;
            for (size_t at = 0; at < total; at += seg_bytes) {
                const size_t n = total - at < seg_bytes ? total - at : seg_bytes;
                size_t len;
                Err err;
                double t0 = timer_now();
                int used = pixcodec_encode(pc, codings[c], px + at, n, bpp, out, &len, &err);
                double t1 = timer_now();
                if (used < 0 || pixcodec_decode(pc, (uint32_t)used, out, len, back, n, bpp, &err) ||
                    memcmp(back, px + at, n)) {
                    fprintf(stderr, "codec_bench: %s: a segment did not come back the same\n",
                            pixcodec_name(codings[c]));
                    free(out), free(back);
                    return 1;
                }
                double t2 = timer_now();
                enc += t1 - t0, dec += t2 - t1;
                coded += len, segs++, raw_kept += used == PIX_RAW && codings[c] != PIX_RAW;
            }
            best_enc = enc < best_enc ? enc : best_enc;
            best_dec = dec < best_dec ? dec : best_dec;
        }
        char seg[24];
        if (lines >= h)
            snprintf(seg, sizeof seg, "whole frame");
        else
            snprintf(seg, sizeof seg, "%d line%s", lines, lines == 1 ? "" : "s");
        printf("  %-4s %-12s %-13s %6.3f of raw  %8.1f us to code  %8.1f us to decode a segment  (%zu of %zu kept raw)\n",
               bpp == 4 ? "RGBE" : "RGB8", seg, pixcodec_name(codings[c]), (double)coded / (double)total,
               1e6 * best_enc / (double)segs, 1e6 * best_dec / (double)segs, raw_kept, segs);
    }
    free(out);
    free(back);
    return 0;
}

int main(int argc, char **argv)
{
    const char *path = NULL;
    int w = 1024, h = 768, rounds = 5;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--width") && i + 1 < argc)
            w = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--height") && i + 1 < argc)
            h = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--rounds") && i + 1 < argc)
            rounds = atoi(argv[++i]);
        else if (argv[i][0] != '-')
            path = argv[i];
        else
            return fprintf(stderr, "usage: codec_bench [SCENE] [--width W] [--height H] [--rounds N]\n"), 2;
    }
    if (w < 1 || h < 1 || rounds < 1)
        return fprintf(stderr, "codec_bench: bad size or rounds\n"), 2;
    Err err;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Scene *s;
    RenderPool *pool = render_pool_create(2, &err);
    PixCodec *pc = pixcodec_create();
    if (!pool || !pc || (path ? scene_load(path, &opt, 0, &s, &err) : scene_default(&s, &opt, &err)))
        return fprintf(stderr, "codec_bench: %s\n", pc ? err.msg : "out of memory"), 1;
    printf("codec_bench: %s, %dx%d, one sample a pixel; bytes of the coded segments against raw, best of %d rounds\n",
           path ? path : "default scene", w, h, rounds);
    int rc = 0;
    for (int hdr = 0; hdr < 2 && rc == 0; hdr++) {
        s->settings.aa = 1, s->settings.adaptive = 0, s->settings.hdr = hdr;
        World *world = world_build(s, NULL, &err);
        uint32_t bpp = (uint32_t)render_pixel_bytes(&s->settings);
        uint8_t *px = world ? malloc((size_t)w * (size_t)h * bpp) : NULL;
        if (!px || render_lines(pool, world, w, h, 0, h, px, NULL, &err)) {
            fprintf(stderr, "codec_bench: %s\n", px ? err.msg : "render failed");
            rc = 1;
        }
        const int seg_lines[] = {1, 2, 16, h};
        for (int k = 0; k < 4 && rc == 0; k++)
            rc = bench_segments(pc, px, w, h, bpp, seg_lines[k], rounds);
        free(px);
        world_destroy(world);
    }
    pixcodec_destroy(pc);
    render_pool_destroy(pool);
    scene_destroy(s);
    return rc;
}

/* pixcodec.h - a segment's pixels as a DATA packet carries them: raw, or
 * through a fast lossless codec from a Debian library (zstd at level 1,
 * or LZ4), optionally after a left-neighbour predictor (each byte minus
 * the same channel of the pixel before it in the segment).  The encoder
 * keeps the raw bytes where the codec does not make them smaller; the
 * decoder writes exactly the segment's bytes or fails, so that a packet
 * that claims more than its pixels, or decodes to more or fewer, is
 * refused before anything past its segment is touched. */
#ifndef LANRAY_PIXCODEC_H
#define LANRAY_PIXCODEC_H

#include <stddef.h>
#include <stdint.h>

#include "base/err.h"

/* A DATA packet's coding: the codec, plus PIX_PREDICT where the predictor ran first. */
enum { PIX_RAW = 0, PIX_ZSTD = 1, PIX_LZ4 = 2, PIX_CODECS = 3, PIX_PREDICT = 0x100 };

/* The codecs this build has, as HELLO's bit mask (1 << codec). */
#define PIX_CODEC_MASK ((1u << PIX_RAW) | (1u << PIX_ZSTD) | (1u << PIX_LZ4))

typedef struct PixCodec PixCodec;

/* One per thread that encodes or decodes (its compression contexts and its
 * scratch, kept from packet to packet: no allocation once warm). */
PixCodec *pixcodec_create(void);
void pixcodec_destroy(PixCodec *c);

/* The most bytes pixcodec_encode may write for n raw bytes. */
size_t pixcodec_bound(size_t n);

/* Codes n bytes of pixels (bpp bytes each) as `coding` asks (a codec, with
 * or without PIX_PREDICT) into out (at least pixcodec_bound(n) bytes):
 * returns the coding used, PIX_RAW where the codec saved nothing (out then
 * holds the raw bytes), or -1 with err where memory ran out. */
int pixcodec_encode(PixCodec *c, uint32_t coding, const uint8_t *px, size_t n, uint32_t bpp, uint8_t *out,
                    size_t *out_len, Err *err);

/* Whether coding is one this build decodes: a codec, with PIX_PREDICT or
 * not (raw without). */
int pixcodec_known(uint32_t coding);

/* Decodes `len` bytes coded as `coding` into dst, which takes exactly n
 * bytes (bpp each): 0, or -1 with err naming what was wrong (an unknown
 * coding, a coded size larger than the raw one, data that does not decode
 * to exactly n bytes). */
int pixcodec_decode(PixCodec *c, uint32_t coding, const uint8_t *in, size_t len, uint8_t *dst, size_t n, uint32_t bpp,
                    Err *err);

/* "raw", "zstd", "lz4", with "+predict". */
const char *pixcodec_name(uint32_t coding);

#endif

/* image.h - writing RGB8 frames as PNG (libpng) or binary PPM, and high
 * dynamic range frames (RGBE: three 8-bit mantissas sharing an 8-bit
 * exponent, 4 bytes a pixel) as Radiance .hdr, atomically, whole or in
 * bands. */
#ifndef LANRAY_IMAGE_H
#define LANRAY_IMAGE_H

#include <stdint.h>
#include <stdio.h>

#include "base/cursor.h"
#include "base/err.h"

/* What the 8-bit values are: sRGB-encoded (what lanray writes unless told
 * --linear) or linear light.  A PNG says which in its sRGB or gAMA chunk. */
typedef enum { IMAGE_SRGB = 0, IMAGE_LINEAR = 1, IMAGE_RGBE = 2 } ImageEncoding;

/* The format follows the extension: .png or .ppm (RGB8), .hdr (RGBE);
 * anything else fails. */
int image_check_name(const char *path, Err *err);
/* Whether the name asks for a high dynamic range image (.hdr). */
int image_is_hdr(const char *path);
int image_write(const char *path, int width, int height, const uint8_t *rgb, ImageEncoding enc, Err *err);

/* Writing an image a band of rows at a time, for frames too large to hold
 * whole: open creates the temporary file at once (so a bad name or
 * directory fails before any rendering), close renames it into place once
 * every row is written.  Any failure, or abort, removes it and frees the
 * writer. */
typedef struct ImageWriter ImageWriter;
int image_writer_open(const char *path, int width, int height, ImageEncoding enc, ImageWriter **out, Err *err);
int image_writer_rows(ImageWriter *wr, const uint8_t *rgb, int rows, Err *err);
int image_writer_close(ImageWriter *wr, Err *err);
void image_writer_abort(ImageWriter *wr);
/* Reads a PNG into a malloc'd 8-bit RGB buffer, with the values as stored
 * (no gamma conversion: a linear frame keeps its codes). */
int image_read_png(const char *path, int *width, int *height, uint8_t **rgb, Err *err);
/* The same from an open stream, which it closes; `name` labels errors. */
int image_read_png_stream(FILE *f, const char *name, int *width, int *height, uint8_t **rgb, Err *err);
/* The same, refusing (before allocating) an image wider or taller than
 * max_side; with `alpha`, an image with transparency (an alpha channel or
 * a tRNS chunk) also gives its w x h alphas there (malloc'd), else NULL. */
int image_read_png_limited(FILE *f, const char *name, uint32_t max_side, int *width, int *height, uint8_t **rgb,
                           uint8_t **alpha, Err *err);

/* 8-bit RGB (w x h, as given: no colour chunk) as a PNG into out, compressed
 * hard: for textures that are stored, not frames written often. */
int image_encode_png(const uint8_t *rgb, int w, int h, Sink *out);
/* The same with w x h alphas beside the colours (an RGBA PNG), or none (NULL). */
int image_encode_png_alpha(const uint8_t *rgb, const uint8_t *alpha, int w, int h, Sink *out);

#endif

/* image.c - see image.h. */
#include "image/image.h"

#include <errno.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/fileio.h"

struct ImageWriter {
    AtomicFile file;
    int w, h, rows, png, bpp;
    png_structp ps;
    png_infop info;
};

/* libpng reports through these instead of printing; the message ends up in the Err */
static void png_error_fn(png_structp png, png_const_charp msg)
{
    err_set(png_get_error_ptr(png), "png: %s", msg);
    png_longjmp(png, 1);
}

static void png_warning_fn(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

static int has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    return n >= e && strcasecmp(path + n - e, ext) == 0;
}

int image_check_name(const char *path, Err *err)
{
    if (!has_ext(path, ".png") && !has_ext(path, ".ppm") && !has_ext(path, ".hdr"))
        return err_set(err, "%s: unknown image format (use .png, .ppm or .hdr)", path);
    return 0;
}

int image_is_hdr(const char *path) { return has_ext(path, ".hdr"); }

void image_writer_abort(ImageWriter *wr)
{
    if (!wr)
        return;
    if (wr->ps)
        png_destroy_write_struct(&wr->ps, &wr->info);
    file_atomic_abort(&wr->file);
    free(wr);
}

/* A failed write (full disk, file size limit) says why. */
static int write_failed(ImageWriter *wr, Err *err)
{
    int e = errno;
    int rc = ferror(wr->file.f) ? err_set(err, "%s: write failed: %s", wr->file.path, strerror(e)) : err_prefix(err, "%s", wr->file.path);
    image_writer_abort(wr);
    return rc;
}

int image_writer_open(const char *path, int width, int height, ImageEncoding enc, ImageWriter **out, Err *err)
{
    *out = NULL;
    if (image_check_name(path, err))
        return -1;
    if (width < 1 || height < 1)
        return err_set(err, "%s: image of %dx%d pixels", path, width, height);
    ImageWriter *wr = calloc(1, sizeof *wr);
    if (!wr)
        return err_set(err, "%s: out of memory", path);
    wr->w = width;
    wr->h = height;
    wr->png = has_ext(path, ".png");
    wr->bpp = enc == IMAGE_RGBE ? 4 : 3;
    if ((enc == IMAGE_RGBE) != image_is_hdr(path)) {
        free(wr);
        return err_set(err, "%s: %s", path, enc == IMAGE_RGBE ? "high dynamic range pixels go to a .hdr file"
                                                               : "a .hdr file takes high dynamic range pixels");
    }
    if (file_atomic_open(&wr->file, path, err)) {
        free(wr);
        return -1;
    }
    if (enc == IMAGE_RGBE) {
        /* Radiance: flat (not run-length encoded) scanlines, top row first */
        fprintf(wr->file.f, "#?RADIANCE\n# written by lanray\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n-Y %d +X %d\n", height,
                width);
        *out = wr;
        return 0;
    }
    if (!wr->png) {
        fprintf(wr->file.f, "P6\n%d %d\n255\n", width, height);
        *out = wr;
        return 0;
    }
    wr->ps = png_create_write_struct(PNG_LIBPNG_VER_STRING, err, png_error_fn, png_warning_fn);
    wr->info = wr->ps ? png_create_info_struct(wr->ps) : NULL;
    if (!wr->info) {
        image_writer_abort(wr);
        return err_set(err, "%s: png: out of memory", path);
    }
    if (setjmp(png_jmpbuf(wr->ps)))
        return write_failed(wr, err);
    png_init_io(wr->ps, wr->file.f);
    png_set_IHDR(wr->ps, wr->info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    /* what the numbers mean, so that viewers show them right: sRGB (with
     * its gAMA and cHRM for readers that know no sRGB chunk), or linear */
    if (enc == IMAGE_SRGB)
        png_set_sRGB_gAMA_and_cHRM(wr->ps, wr->info, PNG_sRGB_INTENT_PERCEPTUAL);
    else
        png_set_gAMA(wr->ps, wr->info, 1.0);
    /* frames are written often: favour speed.  libpng's default tries
     * the five row filters on every row and keeps the smallest; that
     * choice alone took half of a 1024x768 frame's time (a smooth moving
     * frame: 65 of 71 ms at level 3 adaptive, 34 ms at level 1 with the
     * left neighbour's filter, for 11% more bytes) */
    png_set_compression_level(wr->ps, 1);
    png_set_filter(wr->ps, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_write_info(wr->ps, wr->info);
    *out = wr;
    return 0;
}

int image_writer_rows(ImageWriter *wr, const uint8_t *rgb, int rows, Err *err)
{
    if (rows < 0 || rows > wr->h - wr->rows) {
        err_set(err, "%s: %d rows more than the image's %d", wr->file.path, wr->rows + rows, wr->h);
        image_writer_abort(wr);
        return -1;
    }
    size_t stride = (size_t)wr->w * (size_t)wr->bpp;
    if (!wr->png) {
        if (fwrite(rgb, stride, (size_t)rows, wr->file.f) != (size_t)rows)
            return write_failed(wr, err);
    } else {
        if (setjmp(png_jmpbuf(wr->ps)))
            return write_failed(wr, err);
        for (int y = 0; y < rows; y++)
            png_write_row(wr->ps, rgb + (size_t)y * stride);
    }
    wr->rows += rows;
    return 0;
}

int image_writer_close(ImageWriter *wr, Err *err)
{
    if (wr->rows != wr->h) {
        err_set(err, "%s: %d of %d rows written", wr->file.path, wr->rows, wr->h);
        image_writer_abort(wr);
        return -1;
    }
    if (wr->png) {
        if (setjmp(png_jmpbuf(wr->ps)))
            return write_failed(wr, err);
        png_write_end(wr->ps, NULL);
        png_destroy_write_struct(&wr->ps, &wr->info);
    }
    int rc = file_atomic_commit(&wr->file, err);
    free(wr);
    return rc;
}

int image_write(const char *path, int width, int height, const uint8_t *rgb, ImageEncoding enc, Err *err)
{
    ImageWriter *wr;
    if (image_writer_open(path, width, height, enc, &wr, err) || image_writer_rows(wr, rgb, height, err))
        return -1;
    return image_writer_close(wr, err);
}

/* The low-level reader, not png_image: the simplified API converts what a
 * gAMA chunk says to sRGB, and a frame must come back with the codes it was
 * written with (a --linear frame compared with its reference). */
typedef struct {
    FILE *f;
    png_structp png;
    png_infop info;
    uint8_t *buf;
    uint8_t *alpha; /* the alphas, where the caller asked and the image has them */
    png_bytep *rows;
} PngRead;

/* Frees what the reader holds, and the reader (heap, so that what libpng's
 * longjmp leaves is in memory, not in registers setjmp does not restore). */
static void png_read_free(PngRead *r, int keep_pixels)
{
    if (r->png)
        png_destroy_read_struct(&r->png, r->info ? &r->info : NULL, NULL);
    if (r->f)
        fclose(r->f);
    free(r->rows);
    if (!keep_pixels) {
        free(r->buf);
        free(r->alpha);
    }
    free(r);
}

int image_read_png(const char *path, int *width, int *height, uint8_t **rgb, Err *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return err_set(err, "%s: cannot open: %s", path, strerror(errno));
    return image_read_png_stream(f, path, width, height, rgb, err);
}

int image_read_png_stream(FILE *f, const char *path, int *width, int *height, uint8_t **rgb, Err *err)
{
    return image_read_png_limited(f, path, 65536, width, height, rgb, NULL, err);
}

/* RGBA rows (4 bytes a pixel) into RGB in place, the alphas into a. */
static void png_split_alpha(uint8_t *px, uint8_t *a, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        a[i] = px[4 * i + 3];
        px[3 * i] = px[4 * i], px[3 * i + 1] = px[4 * i + 1], px[3 * i + 2] = px[4 * i + 2];
    }
}

int image_read_png_limited(FILE *f, const char *path, uint32_t max_side, int *width, int *height, uint8_t **rgb,
                           uint8_t **alpha, Err *err)
{
    if (alpha)
        *alpha = NULL;
    PngRead *r = calloc(1, sizeof *r);
    if (!r) {
        fclose(f);
        return err_set(err, "%s: out of memory", path);
    }
    r->f = f;
    uint8_t sig[8];
    if (fread(sig, 1, 8, r->f) != 8 || png_sig_cmp(sig, 0, 8) != 0) {
        png_read_free(r, 0);
        return err_set(err, "%s: not a PNG file", path);
    }
    r->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, err, png_error_fn, png_warning_fn);
    r->info = r->png ? png_create_info_struct(r->png) : NULL;
    if (!r->info) {
        png_read_free(r, 0);
        return err_set(err, "%s: png: out of memory", path);
    }
    if (setjmp(png_jmpbuf(r->png))) {
        png_read_free(r, 0);
        return err_prefix(err, "%s", path);
    }
    png_init_io(r->png, r->f);
    png_set_sig_bytes(r->png, 8);
    png_read_info(r->png, r->info);
    png_uint_32 w = png_get_image_width(r->png, r->info), h = png_get_image_height(r->png, r->info);
    /* a size from outside: checked before the pixels are allocated */
    if (w < 1 || h < 1 || w > max_side || h > max_side || (uint64_t)w * h > ((uint64_t)1 << 30))
        png_error(r->png, "image size out of range");
    /* any PNG to 8-bit RGB, values as stored; with its alpha (a channel or
     * a tRNS chunk) beside where the caller asks for it */
    const int ct = png_get_color_type(r->png, r->info);
    const int keep_a = alpha && ((ct & PNG_COLOR_MASK_ALPHA) || png_get_valid(r->png, r->info, PNG_INFO_tRNS));
    const size_t bpp = keep_a ? 4 : 3;
    png_set_expand(r->png);
    png_set_strip_16(r->png);
    if (!keep_a)
        png_set_strip_alpha(r->png);
    png_set_gray_to_rgb(r->png);
    png_read_update_info(r->png, r->info);
    if (png_get_rowbytes(r->png, r->info) != (size_t)w * bpp)
        png_error(r->png, "unexpected row layout");
    r->buf = malloc((size_t)w * h * bpp);
    r->alpha = keep_a ? malloc((size_t)w * h) : NULL;
    r->rows = malloc(h * sizeof *r->rows);
    if (!r->buf || !r->rows || (keep_a && !r->alpha))
        png_error(r->png, "out of memory");
    for (png_uint_32 y = 0; y < h; y++)
        r->rows[y] = r->buf + (size_t)y * w * bpp;
    png_read_image(r->png, r->rows);
    png_read_end(r->png, NULL);
    if (keep_a) {
        png_split_alpha(r->buf, r->alpha, (size_t)w * h);
        *alpha = r->alpha;
    }
    *width = (int)w;
    *height = (int)h;
    *rgb = r->buf;
    png_read_free(r, 1);
    return 0;
}

static void png_to_sink(png_structp png, png_bytep data, png_size_t n) { sink_put(png_get_io_ptr(png), data, n); }
static void png_flush_nothing(png_structp png) { (void)png; }

int image_encode_png(const uint8_t *rgb, int w, int h, Sink *out) { return image_encode_png_alpha(rgb, NULL, w, h, out); }

int image_encode_png_alpha(const uint8_t *rgb, const uint8_t *alpha, int w, int h, Sink *out)
{
    Err err;
    png_structp ps = png_create_write_struct(PNG_LIBPNG_VER_STRING, &err, png_error_fn, png_warning_fn);
    png_infop info = ps ? png_create_info_struct(ps) : NULL;
    if (!info) {
        png_destroy_write_struct(&ps, NULL);
        return -1;
    }
    png_set_write_fn(ps, out, png_to_sink, png_flush_nothing);
    uint8_t *volatile row = alpha ? malloc((size_t)w * 4) : NULL; /* volatile: kept across libpng's longjmp */
    if (alpha && !row) {
        png_destroy_write_struct(&ps, &info);
        return -1;
    }
    if (setjmp(png_jmpbuf(ps))) {
        free(row);
        png_destroy_write_struct(&ps, &info);
        return -1;
    }
    png_set_IHDR(ps, info, (png_uint_32)w, (png_uint_32)h, 8, alpha ? PNG_COLOR_TYPE_RGBA : PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(ps, 9);
    png_write_info(ps, info);
    for (int y = 0; y < h; y++) {
        const uint8_t *src = rgb + (size_t)y * (size_t)w * 3;
        if (alpha) {
            for (int x = 0; x < w; x++) {
                memcpy(&row[4 * x], &src[3 * x], 3);
                row[4 * x + 3] = alpha[(size_t)y * (size_t)w + (size_t)x];
            }
            src = row;
        }
        png_write_row(ps, (png_const_bytep)src);
    }
    png_write_end(ps, NULL);
    free(row);
    png_destroy_write_struct(&ps, &info);
    return out->failed ? -1 : 0;
}

/* image.c - see image.h. */
#include "image.h"

#include <errno.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "fileio.h"

typedef struct {
    int w, h;
    const uint8_t *rgb;
} Frame;

static int write_ppm(FILE *f, void *ctx, Err *err)
{
    Frame *fr = ctx;
    (void)err;
    fprintf(f, "P6\n%d %d\n255\n", fr->w, fr->h);
    fwrite(fr->rgb, 3, (size_t)fr->w * (size_t)fr->h, f);
    return 0;
}

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

static int write_png(FILE *f, void *ctx, Err *err)
{
    Frame *fr = ctx;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, err, png_error_fn, png_warning_fn);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info) {
        png_destroy_write_struct(&png, NULL);
        return err_set(err, "png: out of memory");
    }
    if (setjmp(png_jmpbuf(png))) {
        int e = errno;
        png_destroy_write_struct(&png, &info);
        /* a failed write (full disk, file size limit) says why */
        return ferror(f) ? err_set(err, "write failed: %s", strerror(e)) : -1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)fr->w, (png_uint_32)fr->h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 3); /* frames are written often: favour speed */
    png_write_info(png, info);
    for (int y = 0; y < fr->h; y++)
        png_write_row(png, fr->rgb + (size_t)y * (size_t)fr->w * 3);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return 0;
}

static int has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    return n >= e && strcasecmp(path + n - e, ext) == 0;
}

int image_write(const char *path, int width, int height, const uint8_t *rgb, Err *err)
{
    Frame fr = {width, height, rgb};
    if (has_ext(path, ".png"))
        return file_write_atomic(path, write_png, &fr, err);
    if (has_ext(path, ".ppm"))
        return file_write_atomic(path, write_ppm, &fr, err);
    return err_set(err, "%s: unknown image format (use .png or .ppm)", path);
}

int image_read_png(const char *path, int *width, int *height, uint8_t **rgb, Err *err)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path))
        return err_set(err, "%s: %s", path, img.message);
    img.format = PNG_FORMAT_RGB;
    size_t size = PNG_IMAGE_SIZE(img);
    uint8_t *buf = malloc(size);
    if (!buf) {
        png_image_free(&img);
        return err_set(err, "%s: out of memory", path);
    }
    if (!png_image_finish_read(&img, NULL, buf, 0, NULL)) {
        free(buf);
        return err_set(err, "%s: %s", path, img.message);
    }
    *width = (int)img.width;
    *height = (int)img.height;
    *rgb = buf;
    return 0;
}

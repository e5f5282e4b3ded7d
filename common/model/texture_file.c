/* texture_file.c - texture images by file type: PNG (libpng, through
 * image.c's reader), JPEG (libjpeg-turbo) and PPM/PGM (libnetpbm, in
 * texture.c).  Every reader checks the image's size against
 * TEXTURE_MAX_SIDE before it allocates the pixels. */
#include <ctype.h>
#include <errno.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <jpeglib.h>

#include "model/image.h"
#include "model/texture.h"

static int has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), m = strlen(ext);
    if (n < m)
        return 0;
    for (size_t i = 0; i < m; i++)
        if (tolower((unsigned char)path[n - m + i]) != ext[i])
            return 0;
    return 1;
}

typedef struct {
    struct jpeg_error_mgr pub;
    jmp_buf jump;
    char msg[JMSG_LENGTH_MAX];
} JpegErr;

static void jpeg_fail(j_common_ptr c)
{
    JpegErr *e = (JpegErr *)c->err;
    (*c->err->format_message)(c, e->msg);
    longjmp(e->jump, 1);
}

static void jpeg_quiet(j_common_ptr c, int level) { (void)c, (void)level; }

/* libjpeg reports errors by longjmp: everything it owns is released on the way out */
/* A JPEG decoder fills what a stream lacks with grey and goes on, so a
 * 251-byte file claiming 16384x8192 texels took ten seconds (fuzz_jpeg):
 * the texels claimed must be backed by the file's bytes, with a margin far
 * above what real images need (a flat colour compresses to about 128 texels
 * a byte; this allows 4096). */
#define JPEG_TEXELS_PER_BYTE 4096u
#define JPEG_TEXELS_FREE 65536u

int texture_read_jpeg_stream(FILE *f, const char *name, size_t bytes, Texture **out, Err *err)
{
    struct jpeg_decompress_struct cinfo;
    JpegErr je;
    uint8_t *volatile rgb = NULL;
    cinfo.err = jpeg_std_error(&je.pub);
    je.pub.error_exit = jpeg_fail;
    je.pub.emit_message = jpeg_quiet;
    if (setjmp(je.jump)) {
        jpeg_destroy_decompress(&cinfo);
        free(rgb);
        return err_set(err, "%s: not a JPEG image lanray can read: %s", name, je.msg);
    }
    jpeg_create_decompress(&cinfo);
    jpeg_stdio_src(&cinfo, f);
    jpeg_read_header(&cinfo, TRUE);
    if (cinfo.image_width < 1 || cinfo.image_height < 1 || cinfo.image_width > TEXTURE_MAX_SIDE ||
        cinfo.image_height > TEXTURE_MAX_SIDE) {
        uint32_t w = cinfo.image_width, h = cinfo.image_height;
        jpeg_destroy_decompress(&cinfo);
        return err_set(err, "%s: a %ux%u image exceeds the texture limit of %u on a side", name, w, h, TEXTURE_MAX_SIDE);
    }
    if ((uint64_t)cinfo.image_width * cinfo.image_height > (uint64_t)JPEG_TEXELS_PER_BYTE * bytes + JPEG_TEXELS_FREE) {
        uint32_t w = cinfo.image_width, h = cinfo.image_height;
        jpeg_destroy_decompress(&cinfo);
        return err_set(err, "%s: %zu bytes cannot hold a %ux%u image: the file is cut short or corrupt", name, bytes, w, h);
    }
    cinfo.out_color_space = JCS_RGB; /* grey and YCbCr alike come out as RGB */
    jpeg_start_decompress(&cinfo);
    uint32_t w = cinfo.output_width, h = cinfo.output_height;
    rgb = malloc((size_t)w * h * 3);
    if (!rgb) {
        jpeg_destroy_decompress(&cinfo);
        return err_set(err, "%s: out of memory for a %ux%u texture", name, w, h);
    }
    while (cinfo.output_scanline < h) {
        JSAMPROW row = rgb + (size_t)cinfo.output_scanline * w * 3;
        jpeg_read_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
    *out = texture_from_rgb8(w, h, rgb);
    free(rgb);
    return *out ? 0 : err_set(err, "%s: out of memory for a %ux%u texture", name, w, h);
}

int texture_read(const char *path, Texture **out, Err *err)
{
    *out = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        return err_set(err, "%s: cannot open: %s", path, strerror(errno));
    if (has_extension(path, ".png")) {
        int w, h;
        uint8_t *rgb;
        if (image_read_png_limited(f, path, TEXTURE_MAX_SIDE, &w, &h, &rgb, err)) /* closes f */
            return -1;
        *out = texture_from_rgb8((uint32_t)w, (uint32_t)h, rgb);
        free(rgb);
        return *out ? 0 : err_set(err, "%s: out of memory for a %dx%d texture", path, w, h);
    }
    int rc;
    if (has_extension(path, ".jpg") || has_extension(path, ".jpeg")) {
        struct stat sb;
        rc = fstat(fileno(f), &sb) == 0 ? texture_read_jpeg_stream(f, path, (size_t)sb.st_size, out, err)
                                        : err_set(err, "%s: cannot stat: %s", path, strerror(errno));
    } else {
        rc = texture_read_stream(f, path, out, err);
    }
    fclose(f);
    return rc;
}

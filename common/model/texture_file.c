/* texture_file.c - texture images by their first bytes: PNG (libpng,
 * through image.c's reader), JPEG (libjpeg-turbo) and PPM/PGM (libnetpbm,
 * texture_ppm.c), BMP (texture_bmp.c), TGA (texture_tga.c) and Radiance HDR
 * (texture_hdr.c).  Every
 * reader checks the image's size against TEXTURE_MAX_SIDE before it
 * allocates the pixels.  A PNG or a JPEG keeps its file's bytes
 * (texture.h).  Formats that are recognised but not read (GIF, TIFF, DDS,
 * ...) are named in the error, with what to convert them to. */
#include <errno.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jpeglib.h>

#include "base/fileio.h"
#include "image/image.h"
#include "model/texture.h"

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



/* A texture file may be at most this big: a 16384 x 16384 image in any
 * sensible encoding fits. */
#define TEXTURE_MAX_FILE_BYTES ((size_t)1 << 30)

int texture_read(const char *path, Texture **out, Err *err)
{
    *out = NULL;
    char *data;
    size_t len;
    if (file_read_all(path, TEXTURE_MAX_FILE_BYTES, &data, &len, err))
        return -1;
    int rc = texture_read_memory(data, len, path, out, err);
    free(data);
    return rc;
}

static int starts(const uint8_t *p, size_t len, const char *magic, size_t n)
{
    return len >= n && memcmp(p, magic, n) == 0;
}

/* The format of an image lanray does not read, from its bytes; NULL when
 * it is none of them. */
static const char *unread_format(const uint8_t *p, size_t len)
{
    if (starts(p, len, "GIF8", 4))
        return "GIF";
    if (starts(p, len, "RIFF", 4) && len >= 12 && memcmp(p + 8, "WEBP", 4) == 0)
        return "WebP";
    if (starts(p, len, "II*\0", 4) || starts(p, len, "MM\0*", 4))
        return "TIFF";
    if (starts(p, len, "DDS ", 4))
        return "DDS";
    if (starts(p, len, "8BPS", 4))
        return "Photoshop";
    if (starts(p, len, "\x76\x2f\x31\x01", 4))
        return "OpenEXR";
    if (starts(p, len, "\xabKTX", 4))
        return "KTX";
    return NULL;
}

/* A TGA has no magic: its name says it (".tga", or an embedded image's
 * format hint "(tga)"), or the footer of a TGA 2.0 file. */
static int is_tga(const uint8_t *p, size_t len, const char *name)
{
    return file_has_suffix(name, ".tga") || file_has_suffix(name, "(tga)") ||
           starts(p + (len >= 18 ? len - 18 : 0), len >= 18 ? 18 : 0, "TRUEVISION-XFILE", 16);
}

/* A copy of the image's bytes, to keep with the texture. */
static uint8_t *keep_bytes(const void *data, size_t len)
{
    uint8_t *k = malloc(len ? len : 1);
    if (k)
        memcpy(k, data, len);
    return k;
}

int texture_read_memory(const void *data, size_t len, const char *name, Texture **out, Err *err)
{
    *out = NULL;
    const uint8_t *p = data;
    const int png = starts(p, len, "\x89PNG\r\n\x1a\n", 8), jpeg = starts(p, len, "\xff\xd8\xff", 3);
    const int pnm = len >= 2 && p[0] == 'P' && p[1] >= '1' && p[1] <= '6';
    if (!png && !jpeg && !pnm) {
        if (starts(p, len, "BM", 2))
            return texture_read_bmp(p, len, name, out, err);
        if (is_tga(p, len, name))
            return texture_read_tga(p, len, name, out, err);
        if (starts(p, len, "#?RADIANCE", 10) || starts(p, len, "#?RGBE", 6))
            return texture_read_hdr(p, len, name, out, err);
        const char *fmt = unread_format(p, len);
        if (fmt)
            return err_set(err, "%s: a %s image: lanray reads PNG, JPEG, PPM, PGM, BMP, TGA and Radiance HDR textures (convert it to PNG)",
                           name, fmt);
        return err_set(err, "%s: not an image lanray reads (PNG, JPEG, PPM, PGM, BMP, TGA or Radiance HDR): %s", name,
                       len == 0 ? "the file is empty" : "its first bytes are none of theirs");
    }
    FILE *f = fmemopen((void *)(uintptr_t)data, len, "rb");
    if (!f)
        return err_set(err, "%s: cannot read the image from memory: %s", name, strerror(errno));
    if (pnm) {
        int rc = texture_read_stream(f, name, out, err);
        fclose(f);
        return rc;
    }
    if (jpeg) {
        Texture *t;
        int rc = texture_read_jpeg_stream(f, name, len, &t, err);
        fclose(f);
        if (rc)
            return rc;
        uint8_t *k = keep_bytes(data, len);
        if (!k) {
            texture_destroy(t);
            return err_set(err, "%s: out of memory", name);
        }
        t->file = k, t->file_len = len, t->codec = TEXTURE_JPEG;
        *out = t;
        return 0;
    }
    int w, h;
    uint8_t *rgb, *alpha;
    if (image_read_png_limited(f, name, TEXTURE_MAX_SIDE, &w, &h, &rgb, &alpha, err)) /* closes f */
        return -1;
    *out = texture_with_alpha(
        texture_from_file_rgb8((uint32_t)w, (uint32_t)h, rgb, keep_bytes(data, len), len, TEXTURE_PNG), alpha);
    free(rgb);
    free(alpha);
    if (*out && !(*out)->file) {
        texture_destroy(*out);
        *out = NULL;
    }
    return *out ? 0 : err_set(err, "%s: out of memory for a %dx%d texture", name, w, h);
}

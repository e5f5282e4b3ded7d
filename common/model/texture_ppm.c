/* texture_ppm.c - PPM/PGM textures through libnetpbm.
 *
 * libnetpbm reports errors by calling pm_error(), which exits the process by
 * default.  We install a jump buffer (pm_setjmpbuf) and a message hook so
 * that a bad file becomes an error message instead; the size is checked
 * against TEXTURE_MAX_SIDE, and against the bytes that follow the header,
 * before any pixel memory is allocated.  Samples of any depth become the
 * nearest 8-bit code (they are sRGB-encoded fractions of maxval). */
#include "model/texture.h"

#include <errno.h>
#include <netpbm/pam.h>
#include <setjmp.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

static char pm_last_error[256];

static void capture_pm_error(const char *msg)
{
    snprintf(pm_last_error, sizeof pm_last_error, "%s", msg);
    size_t n = strlen(pm_last_error);
    while (n && (pm_last_error[n - 1] == '\n' || pm_last_error[n - 1] == ' '))
        pm_last_error[--n] = 0;
}

static void quiet_pm_message(const char *msg) { (void)msg; }

int texture_read_stream(FILE *f, const char *name, Texture **out, Err *err)
{
    static int initialised;
    if (!initialised) {
        pm_init("lanray", 0);
        pm_setusererrormsgfn(capture_pm_error);
        pm_setusermessagefn(quiet_pm_message);
        initialised = 1;
    }
    *out = NULL;
    /* only PBM/PGM/PPM (P1..P6): libnetpbm's PAM (P7) header parser leaks
     * memory when it rejects a file, and textures do not need PAM */
    int c0 = getc(f), c1 = getc(f);
    if (c0 != 'P' || c1 < '1' || c1 > '6')
        return err_set(err, "%s: not a valid PPM/PGM image: the file does not start with P1..P6", name);
    if (ungetc(c1, f) == EOF || ungetc(c0, f) == EOF) /* only one push-back is guaranteed: re-open the stream's start */
        if (fseek(f, 0, SEEK_SET) != 0)
            return err_set(err, "%s: cannot rewind the stream", name);
    struct pam pam;
    uint8_t *volatile rgb = NULL;
    tuple *volatile row = NULL;
    jmp_buf jb, *saved;
    pm_last_error[0] = 0;
    pm_setjmpbufsave(&jb, &saved);
    if (setjmp(jb) != 0) {
        pm_setjmpbuf(saved);
        if (row)
            pnm_freepamrow(row);
        free(rgb);
        return err_set(err, "%s: not a valid PPM/PGM image: %s", name, pm_last_error[0] ? pm_last_error : "unknown error");
    }
    /* the struct up to tuple_type, as PAM_STRUCT_SIZE(tuple_type) means but
     * without its offset through a null pointer (UB); later fields (comments)
     * would make netpbm allocate strings we do not want */
    memset(&pam, 0, sizeof pam);
    pnm_readpaminit(f, &pam, (int)(offsetof(struct pam, tuple_type) + sizeof pam.tuple_type));
    int rc = 0;
    if (pam.width < 1 || pam.height < 1 || (uint32_t)pam.width > TEXTURE_MAX_SIDE || (uint32_t)pam.height > TEXTURE_MAX_SIDE)
        rc = err_set(err, "%s: image is %dx%d, textures must be 1..%u pixels on a side", name, pam.width, pam.height,
                     TEXTURE_MAX_SIDE);
    else if (pam.depth != 1 && pam.depth != 3)
        rc = err_set(err, "%s: image has %u channels, expected 1 (grey) or 3 (RGB)", name, pam.depth);
    else if (pam.maxval < 1)
        rc = err_set(err, "%s: maxval %lu is invalid", name, pam.maxval);
    if (rc == 0) {
        /* the header's size must be backed by bytes before anything is
         * allocated: raw formats need their exact sample bytes, plain ones at
         * least one character per sample (checked where the stream can seek) */
        uint64_t samples = (uint64_t)pam.width * (uint64_t)pam.height * pam.depth;
        uint64_t need = c1 == '4' ? (uint64_t)((pam.width + 7) / 8) * (uint64_t)pam.height
                        : c1 >= '5' ? samples * (pam.maxval > 255 ? 2 : 1)
                                    : samples;
        long pos = ftell(f);
        if (pos >= 0 && fseek(f, 0, SEEK_END) == 0) {
            long end = ftell(f);
            fseek(f, pos, SEEK_SET);
            if (end >= pos && (uint64_t)(end - pos) < need)
                rc = err_set(err, "%s: the header promises %dx%d pixels but only %ld bytes follow", name, pam.width,
                             pam.height, end - pos);
        }
    }
    if (rc) {
        pm_setjmpbuf(saved);
        return rc;
    }
    uint32_t w = (uint32_t)pam.width, h = (uint32_t)pam.height;
    rgb = malloc((size_t)w * h * 3);
    if (!rgb) {
        pm_setjmpbuf(saved);
        return err_set(err, "%s: out of memory for a %ux%u texture", name, w, h);
    }
    row = pnm_allocpamrow(&pam);
    for (uint32_t y = 0; y < h; y++) {
        pnm_readpamrow(&pam, row);
        uint8_t *dst = &rgb[(size_t)y * w * 3];
        for (uint32_t x = 0; x < w; x++)
            for (int c = 0; c < 3; c++) {
                /* an sRGB-encoded fraction of maxval: its nearest 8-bit code */
                uint64_t v = row[x][pam.depth == 3 ? c : 0];
                dst[3 * x + c] = v >= pam.maxval ? 255 : (uint8_t)((v * 255 + pam.maxval / 2) / pam.maxval);
            }
    }
    pnm_freepamrow(row);
    row = NULL;
    pm_setjmpbuf(saved);
    *out = texture_from_rgb8(w, h, rgb);
    free(rgb);
    return *out ? 0 : err_set(err, "%s: out of memory for a %ux%u texture", name, w, h);
}

/* texture_hdr.c - a Radiance .hdr image (RGBE) as a texture: its light kept
 * as float RGB (Texture.hdr) for what reads light beyond white (an
 * environment: scene/environment.h), and as sRGB codes clipped to white,
 * with their mip-maps, for what reads colours (a material's texture).  The
 * file's own bytes are kept (run-length coded: some four bytes a texel)
 * for the byte form, which a reader decodes again into the same floats. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/srgb.h"
#include "image/hdr_read.h"
#include "model/texture.h"

int texture_read_hdr(const void *data, size_t len, const char *name, Texture **out, Err *err)
{
    *out = NULL;
    int w, h;
    uint8_t *rgbe;
    if (hdr_parse(data, len, name, &w, &h, &rgbe, err))
        return -1;
    if (!texture_size_ok((uint32_t)w, (uint32_t)h)) {
        free(rgbe);
        return err_set(err, "%s: a %dx%d image exceeds the texture limit of %u on a side", name, w, h,
                       TEXTURE_MAX_SIDE);
    }
    const size_t n = (size_t)w * (size_t)h;
    float *light = malloc(n * 3 * sizeof *light);
    uint8_t *rgb = malloc(n * 3), *file = malloc(len ? len : 1);
    if (!light || !rgb || !file) {
        free(rgbe), free(light), free(rgb), free(file);
        return err_set(err, "%s: out of memory for a %dx%d texture", name, w, h);
    }
    for (size_t i = 0; i < n; i++) {
        double c[3];
        rgbe_decode(rgbe + 4 * i, c);
        for (int k = 0; k < 3; k++) {
            light[3 * i + k] = (float)c[k];
            rgb[3 * i + k] = srgb_encode8((real)fmin(c[k], 1.0));
        }
    }
    free(rgbe);
    memcpy(file, data, len);
    Texture *t = texture_from_file_rgb8((uint32_t)w, (uint32_t)h, rgb, file, len, TEXTURE_HDR);
    free(rgb);
    if (!t) {
        free(light);
        return err_set(err, "%s: out of memory for a %dx%d texture", name, w, h);
    }
    t->hdr = light;
    *out = t;
    return 0;
}

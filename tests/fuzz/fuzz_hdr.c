/* fuzz_hdr.c - Radiance .hdr images (hdr_parse: header, resolution line,
 * flat and run-length coded scanlines) on arbitrary bytes; an accepted
 * image's pixels are all read, and as a texture (texture_read_memory) it
 * becomes an environment (its sampling tables and harmonics made from
 * whatever light the bytes say) that is looked up, drawn from and asked
 * its density. */
#include <stdlib.h>

#include "fuzz.h"
#include "image/hdr_read.h"
#include "scene/environment.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    int w, h;
    uint8_t *px;
    if (hdr_parse(data, size, "fuzz.hdr", &w, &h, &px, NULL) != 0)
        return 0;
    unsigned sum = 0;
    for (size_t i = 0; i < (size_t)w * h * 4; i++)
        sum += px[i];
    free(px);
    Texture *t;
    Err err;
    if (texture_read_memory(data, size, "fuzz.hdr", &t, &err) == 0) {
        Environment *e = environment_create(t, R(1e6), R(37), &err);
        for (int i = 0; e && i < 16; i++) {
            const real u = (real)i / R(16), v = (real)((i * 7) % 16) / R(16);
            vec3 d, l;
            real pdf;
            if (environment_sample(e, u, v, &d, &l, &pdf))
                sum += (unsigned)(environment_pdf(e, d) > R(0));
            const vec3 c = v3_add(environment_radiance(e, v3(u - R(0.5), v, R(0.3))), environment_diffuse(e, v3(0, 1, 0)));
            sum += (unsigned)(c.x != c.x);
        }
        environment_destroy(e);
        texture_destroy(t);
    }
    return (int)(sum & 0);
}

/* fuzz_ppm.c - texture images by their bytes (texture_read_memory: PPM/PGM
 * through libnetpbm, and PNG and JPEG where the bytes start as theirs) on
 * arbitrary bytes; an accepted texture is sampled through every filter over
 * small and huge footprints, and its byte form read back. */
#include <stdio.h>

#include "fuzz.h"
#include "model/texture.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    Texture *t;
    if (texture_read_memory(data, size, "fuzz.ppm", &t, NULL) != 0)
        return 0;
    const TexFootprint fp[3] = {{0.001f, 0, 0, 0.001f}, {0.3f, 0.01f, 0.02f, 0.05f}, {40, 0, 0, 1e-6f}};
    for (int f = 0; f < FILTER_COUNT; f++)
        for (int k = 0; k < 3; k++)
            texture_sample(t, 0.3f, 0.7f, &fp[k], (TextureFilter)f);
    Sink s = {0};
    Texture *back;
    if (texture_encode(t, &s) == 0 && texture_decode(s.data, s.len, "fuzz.form", &back, NULL) == 0)
        texture_destroy(back);
    sink_free(&s);
    texture_destroy(t);
    return 0;
}

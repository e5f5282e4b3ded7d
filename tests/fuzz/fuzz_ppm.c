/* fuzz_ppm.c - PPM/PGM texture loading through libnetpbm on arbitrary bytes. */
#include <stdio.h>

#include "fuzz.h"
#include "model/texture.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    FILE *f = fuzz_file(data, size);
    if (!f)
        return 0;
    Texture *t;
    if (texture_read_stream(f, "fuzz.ppm", &t, NULL) == 0) {
        texture_sample(t, 0.3f, 0.7f, FILTER_BILINEAR);
        texture_destroy(t);
    }
    fclose(f);
    return 0;
}

/* fuzz_jpeg.c - JPEG textures (libjpeg-turbo, texture_file.c) on arbitrary
 * bytes: the size check before allocation, and libjpeg's longjmp errors. */
#include <stdio.h>
#include <stdlib.h>

#include "fuzz.h"
#include "model/texture.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    FILE *f = fuzz_file(data, size);
    if (!f)
        return 0;
    Texture *t;
    Err err;
    if (texture_read_jpeg_stream(f, "fuzz.jpg", size, &t, &err) == 0)
        texture_destroy(t);
    fclose(f);
    return 0;
}

/* fuzz_raster.c - TGA and BMP textures (texture_tga.c, texture_bmp.c) on
 * arbitrary bytes, through texture_read_memory as a model's textures go:
 * the first byte picks the name (a .tga, whose bytes have no magic, or a
 * .bmp, read by its "BM"), the rest is the file. */
#include "fuzz.h"
#include "model/texture.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    Texture *t;
    Err err;
    if (texture_read_memory(data + 1, size - 1, data[0] & 1 ? "fuzz.bmp" : "fuzz.tga", &t, &err) == 0)
        texture_destroy(t);
    return 0;
}

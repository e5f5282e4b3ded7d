/* fuzz_png.c - PNG reading (lanray-server --verify references, lanray-imgdiff
 * inputs) on arbitrary bytes, and again with the alpha a texture keeps for
 * cutouts. */
#include <stdio.h>
#include <stdlib.h>

#include "fuzz.h"
#include "image/image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    FILE *f = fuzz_file(data, size);
    if (!f)
        return 0; /* image_read_png_stream closes it */
    int w, h;
    uint8_t *px;
    if (image_read_png_stream(f, "fuzz.png", &w, &h, &px, NULL) == 0)
        free(px);
    uint8_t *alpha;
    if ((f = fuzz_file(data, size)) && image_read_png_limited(f, "fuzz.png", 16384, &w, &h, &px, &alpha, NULL) == 0) {
        free(px);
        free(alpha);
    }
    return 0;
}

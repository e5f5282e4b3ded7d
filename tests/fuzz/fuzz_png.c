/* fuzz_png.c - PNG reading (lanray-server --verify references, lanray-imgdiff
 * inputs) on arbitrary bytes. */
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
    return 0;
}

/* fuzz_png.c - PNG reading (lanray-server --verify references, lanray-imgdiff
 * inputs) on arbitrary bytes. */
#include <stdio.h>
#include <stdlib.h>

#include "fuzz.h"
#include "model/image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    FILE *f = fmemopen((void *)data, size, "rb");
    if (!f)
        return 0;
    int w, h;
    uint8_t *px;
    if (image_read_png_stream(f, "fuzz.png", &w, &h, &px, NULL) == 0)
        free(px);
    return 0;
}

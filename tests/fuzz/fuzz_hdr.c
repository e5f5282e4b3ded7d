/* fuzz_hdr.c - Radiance .hdr images (hdr_parse: header, resolution line,
 * flat and run-length coded scanlines) on arbitrary bytes; an accepted
 * image's pixels are all read. */
#include <stdlib.h>

#include "fuzz.h"
#include "image/hdr_read.h"

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
    return (int)(sum & 0);
}

/* lanray-imgdiff - compares two PNG frames of the same size.
 *
 *   lanray-imgdiff a.png b.png
 *
 * Prints the largest channel difference, the number of differing pixels,
 * RMSE (0..255 scale) and PSNR in dB.  Exit status 0 when the sizes match,
 * 1 on errors; the numbers are for the caller to judge. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "image.h"

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: lanray-imgdiff a.png b.png\n");
        return 2;
    }
    Err err;
    int wa, ha, wb, hb;
    uint8_t *a, *b;
    if (image_read_png(argv[1], &wa, &ha, &a, &err)) {
        fprintf(stderr, "lanray-imgdiff: %s\n", err.msg);
        return 1;
    }
    if (image_read_png(argv[2], &wb, &hb, &b, &err)) {
        fprintf(stderr, "lanray-imgdiff: %s\n", err.msg);
        free(a);
        return 1;
    }
    if (wa != wb || ha != hb) {
        fprintf(stderr, "lanray-imgdiff: sizes differ: %dx%d and %dx%d\n", wa, ha, wb, hb);
        free(a);
        free(b);
        return 1;
    }
    size_t n = (size_t)wa * (size_t)ha;
    int maxd = 0;
    size_t differing = 0;
    double sq = 0;
    for (size_t i = 0; i < n; i++) {
        int px = 0;
        for (int c = 0; c < 3; c++) {
            int d = abs((int)a[3 * i + c] - (int)b[3 * i + c]);
            if (d > maxd)
                maxd = d;
            px |= d;
            sq += (double)d * d;
        }
        differing += px != 0;
    }
    double rmse = sqrt(sq / (3.0 * (double)n));
    double psnr = rmse > 0 ? 20 * log10(255.0 / rmse) : INFINITY;
    printf("max difference %d, differing pixels %zu of %zu, rmse %.4f, psnr %.2f dB\n", maxd, differing, n, rmse, psnr);
    free(a);
    free(b);
    return 0;
}

/* lanray-imgdiff - compares two PNG frames of the same size.
 *
 *   lanray-imgdiff [--csv] a.png b.png   (--help lists the options and exit statuses)
 *   lanray-imgdiff --relative [--block N] a.hdr reference.hdr
 *
 * --relative compares light (Radiance .hdr, lanray's or another
 * renderer's): the mean relative error of N x N block means, the ratio of
 * the images' means; a reference k times larger a side is taken as k x k
 * blocks (a reference of k^2 times the samples).
 *
 * Prints the largest channel difference, the number of differing pixels,
 * RMSE (0..255 scale), PSNR in dB and SSIM (structural similarity, Wang et
 * al. 2004, on luma in 8x8 windows: 1 = identical, a perceptual measure that
 * weighs structure over uniform brightness errors).  --csv prints
 * "max,differing,rmse,psnr,ssim".  Exit status 0 when the sizes match, 1 on
 * errors; the numbers are for the caller to judge. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/srgb.h"
#include "image/hdr_read.h"
#include "image/image.h"
#include "model/texture.h"
#include "base/opt.h"

/* Mean SSIM over all 8x8 windows (step 1) of the luma channel. */
static double ssim(const uint8_t *a, const uint8_t *b, int w, int h)
{
    enum { N = 8 };
    if (w < N || h < N)
        return 1.0;
    double *ya = malloc(sizeof(double) * (size_t)w * h), *yb = malloc(sizeof(double) * (size_t)w * h);
    if (!ya || !yb) {
        free(ya);
        free(yb);
        return NAN;
    }
    for (size_t i = 0; i < (size_t)w * h; i++) {
        ya[i] = 0.299 * a[3 * i] + 0.587 * a[3 * i + 1] + 0.114 * a[3 * i + 2];
        yb[i] = 0.299 * b[3 * i] + 0.587 * b[3 * i + 1] + 0.114 * b[3 * i + 2];
    }
    const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
    double sum = 0;
    long windows = 0;
    for (int y = 0; y + N <= h; y++)
        for (int x = 0; x + N <= w; x++) {
            double ma = 0, mb = 0, va = 0, vb = 0, cov = 0;
            for (int j = 0; j < N; j++)
                for (int i = 0; i < N; i++) {
                    size_t k = (size_t)(y + j) * w + (x + i);
                    ma += ya[k];
                    mb += yb[k];
                }
            ma /= N * N;
            mb /= N * N;
            for (int j = 0; j < N; j++)
                for (int i = 0; i < N; i++) {
                    size_t k = (size_t)(y + j) * w + (x + i);
                    double da = ya[k] - ma, db = yb[k] - mb;
                    va += da * da;
                    vb += db * db;
                    cov += da * db;
                }
            va /= N * N - 1;
            vb /= N * N - 1;
            cov /= N * N - 1;
            sum += ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
            windows++;
        }
    free(ya);
    free(yb);
    return sum / (double)windows;
}

/* An image as 8-bit RGB: a PNG by libpng (any size, its codes as stored),
 * a PPM, PGM or JPEG by the texture readers (model/texture.h). */
static int read_image(const char *path, int *w, int *h, uint8_t **rgb, Err *err)
{
    FILE *f = fopen(path, "rb");
    unsigned char sig[8] = {0};
    size_t got = f ? fread(sig, 1, sizeof sig, f) : 0;
    if (f)
        fclose(f);
    if (got == 8 && memcmp(sig, "\x89PNG\r\n\x1a\n", 8) == 0)
        return image_read_png(path, w, h, rgb, err);
    Texture *t;
    if (texture_read(path, &t, err))
        return -1;
    size_t n = (size_t)t->w * t->h * 3;
    *rgb = malloc(n);
    if (!*rgb) {
        texture_destroy(t);
        return err_set(err, "%s: out of memory", path);
    }
    memcpy(*rgb, t->level[0].rgb, n);
    *w = (int)t->w, *h = (int)t->h;
    texture_destroy(t);
    return 0;
}

/* The largest channel difference, the pixels that differ at all, and the
 * RMSE (returned) of n RGB8 pixels. */
static double differences(const uint8_t *a, const uint8_t *b, size_t n, int *maxd, size_t *differing)
{
    double sq = 0;
    *maxd = 0, *differing = 0;
    for (size_t i = 0; i < n; i++) {
        int px = 0;
        for (int c = 0; c < 3; c++) {
            int d = abs((int)a[3 * i + c] - (int)b[3 * i + c]);
            if (d > *maxd)
                *maxd = d;
            px |= d;
            sq += (double)d * d;
        }
        *differing += px != 0;
    }
    return sqrt(sq / (3.0 * (double)n));
}

/* The means of b x b blocks of an RGBE image (whole blocks only), as
 * 3 doubles a block. */
static double *block_means(const uint8_t *px, int w, int h, int b, int *nb)
{
    const int bw = w / b, bh = h / b;
    double *m = calloc((size_t)bw * bh * 3 + 1, sizeof *m);
    if (!m)
        return NULL;
    for (int y = 0; y < bh * b; y++)
        for (int x = 0; x < bw * b; x++) {
            double c[3];
            rgbe_decode(px + 4 * ((size_t)y * w + x), c);
            for (int k = 0; k < 3; k++)
                m[3 * ((size_t)(y / b) * bw + x / b) + k] += c[k] / (b * b);
        }
    *nb = bw * bh;
    return m;
}

/* Light against a reference: the mean relative error of the channels of
 * b x b block means, |a - r| / (r + 1% of r's mean) (the 1% keeps black
 * blocks from dividing by zero), and the ratio of the images' means. */
static int relative(const char *pa, const char *pr, int b, int csv)
{
    Err err = {{0}};
    int wa, ha, wr, hr, na, nr;
    uint8_t *a = NULL, *r = NULL;
    if (hdr_read(pa, &wa, &ha, &a, &err) || hdr_read(pr, &wr, &hr, &r, &err)) {
        fprintf(stderr, "lanray-imgdiff: %s\n", err.msg);
        free(a);
        return 1;
    }
    /* a reference k times the size: its k x k blocks are the image's pixels (more samples a pixel) */
    const int k = wr / wa;
    if (k < 1 || wr != k * wa || hr != k * ha || b > wa || b > ha) {
        fprintf(stderr, "lanray-imgdiff: the reference is not the image's size or a whole multiple of it, or the block "
                        "is larger: %dx%d and %dx%d, block %d\n", wa, ha, wr, hr, b);
        free(a);
        free(r);
        return 1;
    }
    double *ma = block_means(a, wa, ha, b, &na), *mr = block_means(r, wr, hr, k * b, &nr);
    free(a);
    free(r);
    if (!ma || !mr) {
        fprintf(stderr, "lanray-imgdiff: out of memory\n");
        free(ma);
        free(mr);
        return 1;
    }
    double sa = 0, sr = 0, rel = 0;
    for (int i = 0; i < 3 * na; i++)
        sa += ma[i], sr += mr[i];
    const double floor = 0.01 * sr / (3.0 * na);
    for (int i = 0; i < 3 * na; i++)
        rel += fabs(ma[i] - mr[i]) / (mr[i] + floor);
    rel /= 3.0 * na;
    const double ratio = sr > 0 ? sa / sr : (double)INFINITY;
    if (csv)
        printf("%.6f,%.6f\n", rel, ratio);
    else
        printf("mean relative error %.4f (%dx%d blocks), mean light %.6g against %.6g (ratio %.4f)\n", rel, b, b,
               sa / (3.0 * na), sr / (3.0 * na), ratio);
    free(ma);
    free(mr);
    return 0;
}

int main(int argc, char **argv)
{
    int csv = 0, rel = 0, block = 1;
    const Opt opts[] = {
        {.name = "--csv", .kind = OPT_FLAG, .dst = &csv,
         .help = "print max,differing,rmse,psnr,ssim on one line (--relative: error,ratio)"},
        {.name = "--relative", .kind = OPT_FLAG, .dst = &rel,
         .help = "compare the light of two .hdr images (the second the reference, its size the first's or a whole "
                 "multiple, taken in blocks): mean relative error and the ratio of their means"},
        {.name = "--block", .kind = OPT_INT, .dst = &block, .lo = 1, .hi = 4096, .arg = "N",
         .help = "--relative: compare means of N x N blocks (noise averages out, bias stays)", .def = "1"},
        {0},
    };
    const char *args[2];
    OptSpec spec = {.prog = "lanray-imgdiff", .synopsis = "[--csv] a.png b.png | --relative [--block N] a.hdr reference.hdr",
                    .about = "Compares two images of the same size (PNG, PPM, PGM or JPEG, by their first bytes): the\n"
                    "largest channel difference, the pixels that differ,\n"
                    "RMSE (0..255), PSNR in dB and SSIM (luma, 8x8 windows; 1 = identical).  The numbers are for the\n"
                    "caller to judge.",
                    .opts = opts, .args = args, .min_args = 2, .max_args = 2, .missing = "needs two images",
                    .exits = "  0  compared (whatever the differences)\n"
                    "  1  an image could not be read, or the sizes differ\n"
                    "  2  bad command line\n"};
    int go = opt_run(&spec, argc, argv);
    if (go != OPT_GO)
        return go;
    if (rel)
        return relative(args[0], args[1], block, csv);
    Err err = {{0}};
    int wa, ha, wb, hb;
    uint8_t *a, *b;
    if (read_image(args[0], &wa, &ha, &a, &err)) {
        fprintf(stderr, "lanray-imgdiff: %s\n", err.msg);
        return 1;
    }
    if (read_image(args[1], &wb, &hb, &b, &err)) {
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
    size_t n = (size_t)wa * (size_t)ha, differing;
    int maxd;
    double rmse = differences(a, b, n, &maxd, &differing);
    double psnr = rmse > 0 ? 20 * log10(255.0 / rmse) : (double)INFINITY;
    double s = ssim(a, b, wa, ha);
    if (csv)
        printf("%d,%zu,%.5f,%.3f,%.6f\n", maxd, differing, rmse, isinf(psnr) ? 999.0 : psnr, s);
    else
        printf("max difference %d, differing pixels %zu of %zu, rmse %.4f, psnr %.2f dB, ssim %.6f\n", maxd, differing, n,
               rmse, psnr, s);
    free(a);
    free(b);
    return 0;
}

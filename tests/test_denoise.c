/* test_denoise.c - the guided filter of path-traced frames
 * (render/denoise.c): a pixel's guide comes back from its bytes (albedo to
 * half a code, normals to a degree, distances to 2^-15, its samples'
 * relative noise to a sixteenth of an octave), and any bytes a client may
 * send decode to finite numbers; a flat noisy frame is smoothed
 * (error down more than four times, its mean kept), a fold between two
 * walls of different light stays a fold (no light across it), a texture's
 * detail under even light stays as it was, a firefly is cut to its
 * neighbours, a highlight whose samples agree stays (one of a single
 * sample a pixel is spread), pixels that saw the background pass byte for byte, RGBE
 * frames are filtered in their light, every frame size down to 1 x 1 gives
 * finite pixels, and a frame is the same bytes whatever threads filter it. */
#include "helpers.h"

#include <math.h>

#include "base/pool.h"
#include "base/srgb.h"
#include "render/denoise.h"

#define G DENOISE_GUIDE_BYTES

/* a deterministic noise in [-1, 1) from an index */
static double noise(uint32_t i)
{
    uint32_t x = i * 2654435761u;
    x ^= x >> 15, x *= 2246822519u, x ^= x >> 13;
    return (double)(x >> 8) / 8388608.0 - 1.0;
}

/* the guide of `samples` samples, each `g` (lum2: their light's squares
 * summed, as a spread of `rel` of the mean's standard error about the
 * mean light c would give) */
static Guide guide_of(const Guide *g, int samples, double c, double rel)
{
    Guide s = {.albedo = v3_scale(g->albedo, (real)samples), .normal = v3_scale(g->normal, (real)samples),
               .depth = g->depth * (real)samples, .surface = g->surface * samples};
    s.lum2 = (real)(samples * (c * c + (samples - 1) * rel * rel * c * c));
    return s;
}

/* one pixel's bytes: sRGB codes of grey light c, then the guide */
static void put_n(uint8_t *p, double c[3], vec3 albedo, vec3 n, real depth, int surface, int samples, double rel)
{
    for (int k = 0; k < 3; k++)
        p[k] = srgb_encode8((real)c[k]);
    const Guide one = {.albedo = albedo, .normal = n, .depth = depth, .surface = surface};
    const double l = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    Guide g = guide_of(&one, samples, l, rel);
    denoise_guide_pack(&g, samples, v3((real)c[0], (real)c[1], (real)c[2]), p + 3);
}

static void put(uint8_t *p, double c[3], vec3 albedo, vec3 n, real depth, int surface)
{
    put_n(p, c, albedo, n, depth, surface, 1, 0);
}

static uint8_t *denoised(const uint8_t *px, uint32_t w, uint32_t h, uint32_t cb, Pool *pool)
{
    uint8_t *out = malloc((size_t)w * h * cb);
    Denoiser *d = denoiser_create(pool, w, h);
    assert_non_null(out);
    assert_non_null(d);
    Err err;
    assert_int_equal(denoise_frame(d, px, w, h, cb, 0, out, &err), 0);
    denoiser_destroy(d);
    return out;
}

static void guides_come_back(void **state)
{
    (void)state;
    uint8_t b[G];
    float a[3], n[3], z, rn;
    for (uint32_t i = 0; i < 20000; i++) {
        vec3 m = v3_norm(v3((real)noise(3 * i), (real)noise(3 * i + 1), (real)noise(3 * i + 2)));
        const real depth = (real)pow(10.0, 6 * noise(7 * i + 5)), alb = (real)(0.5 + 0.5 * noise(11 * i));
        /* from 2^-7 (below it, in float, the squares sum past their difference) to 2 */
        const double rel = pow(2.0, -7 + 8 * (noise(13 * i) * 0.5 + 0.5)), light = 0.01 + noise(17 * i) * 0.005;
        /* three samples: their sums */
        const Guide one = {.albedo = v3_splat(alb), .normal = m, .depth = depth, .surface = 1};
        Guide g = guide_of(&one, 3, light, rel);
        denoise_guide_pack(&g, 3, v3_splat((real)light), b);
        denoise_guide_unpack(b, a, n, &z, &rn);
        assert_true(fabs((double)rn / rel - 1) < 0.045); /* a sixteenth of an octave */
        for (int k = 0; k < 3; k++)
            assert_true(fabs((double)a[k] - (double)alb) <= 0.5 / 255 + 1e-6);
        const double c = (double)n[0] * (double)m.x + (double)n[1] * (double)m.y + (double)n[2] * (double)m.z;
        assert_true(c > cos(3.14159265358979 / 180)); /* within a degree */
        assert_true(fabs((double)z - (double)depth) <= (double)depth / 32768);
    }
    /* no surface: distance 0; normals that cancel still give a unit one */
    Guide sky = {.albedo = v3_splat(R(1)), .normal = v3_splat(R(0)), .depth = R(0), .surface = 0};
    denoise_guide_pack(&sky, 1, v3_splat(R(1)), b);
    denoise_guide_unpack(b, a, n, &z, &rn);
    assert_true(z == 0.0f && a[0] == 1.0f && rn < 0); /* one sample: its noise not known */
    /* two samples that agree: no noise; normals that cancel: a unit one */
    Guide fold = {.albedo = v3_splat(R(2)), .normal = v3_splat(R(0)), .depth = R(4), .surface = 2, .lum2 = R(2 * 0.25)};
    denoise_guide_pack(&fold, 2, v3_splat(R(0.5)), b);
    denoise_guide_unpack(b, a, n, &z, &rn);
    assert_float_equal(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1, 1e-5);
    assert_true(z > 1.99f && z < 2.01f);
    assert_true(rn == 0.0f);
}

/* every distance code, and normals and albedos of every byte: finite, a
 * distance 0 or positive (a client's bytes are outside bytes) */
static void any_bytes_decode_finite(void **state)
{
    (void)state;
    uint8_t b[G];
    float a[3], n[3], z, rn;
    for (uint32_t code = 0; code < (1u << 24); code += TEST_SANITIZED ? 97 : 1) {
        b[0] = (uint8_t)code, b[1] = (uint8_t)(code >> 8), b[2] = (uint8_t)(code >> 16);
        b[3] = (uint8_t)(code >> 4), b[4] = (uint8_t)(code >> 12);
        b[5] = (uint8_t)code, b[6] = (uint8_t)(code >> 8), b[7] = (uint8_t)(code >> 16);
        b[8] = (uint8_t)(code >> 3);
        denoise_guide_unpack(b, a, n, &z, &rn);
        assert_true(isfinite(z) && z >= 0.0f && z <= 1e30f);
        assert_true(isfinite(rn) && rn >= -1.0f && rn < 32.0f);
        assert_true(isfinite(n[0]) && isfinite(n[1]) && isfinite(n[2]));
        assert_true(fabsf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1.0f) < 1e-5f);
        assert_true(a[0] >= 0 && a[0] <= 1);
    }
}

#define W 64
#define H 48

/* light of pixel (x, y) of a frame whose left part (x < split) is lit by
 * la and faces +z, the rest by lb and faces +x, both at distance 5, with
 * noise of relative size amp */
static uint8_t *two_walls(int split, double la, double lb, double amp, double *truth)
{
    uint8_t *px = malloc((size_t)W * H * (3 + G));
    assert_non_null(px);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + (size_t)x;
            const double l = x < split ? la : lb;
            const double v = l * (1 + amp * noise((uint32_t)i));
            double c[3] = {v, v, v};
            put(px + i * (3 + G), c, v3_splat(R(0.8)), x < split ? v3(0, 0, 1) : v3(1, 0, 0), R(5), 1);
            if (truth)
                truth[i] = l;
        }
    return px;
}

static double rmse_of(const uint8_t *out, uint32_t stride, const double *truth, int x0, int x1)
{
    double s = 0;
    int n = 0;
    for (int y = 0; y < H; y++)
        for (int x = x0; x < x1; x++) {
            const size_t i = (size_t)y * W + (size_t)x;
            const double d = (double)srgb_decode8[out[i * stride]] - truth[i];
            s += d * d, n++;
        }
    return sqrt(s / n);
}

static double mean_of(const uint8_t *out, uint32_t stride, int x0, int x1)
{
    double s = 0;
    int n = 0;
    for (int y = 0; y < H; y++)
        for (int x = x0; x < x1; x++, n++)
            s += (double)srgb_decode8[out[((size_t)y * W + (size_t)x) * stride]];
    return s / n;
}

static void a_flat_frame_is_smoothed(void **state)
{
    (void)state;
    double truth[W * H];
    uint8_t *px = two_walls(W, 0.3, 0.3, 0.6, truth);
    uint8_t *out = denoised(px, W, H, 3, NULL);
    const double before = rmse_of(px, 3 + G, truth, 0, W), after = rmse_of(out, 3, truth, 0, W);
    print_message("flat frame: RMSE %.4f -> %.4f, mean %.4f (truth 0.3)\n", before, after, mean_of(out, 3, 0, W));
    assert_true(after < before / 4);
    assert_true(fabs(mean_of(out, 3, 0, W) - 0.3) < 0.3 * 0.03);
    free(px), free(out);
}

/* two walls meeting, one at 0.05 and one at 0.6: near the fold each keeps
 * its own light (a filter blind to the normals would mix them) */
static void a_fold_stays_a_fold(void **state)
{
    (void)state;
    double truth[W * H];
    uint8_t *px = two_walls(W / 2, 0.05, 0.6, 0.5, truth);
    uint8_t *out = denoised(px, W, H, 3, NULL);
    const double left = mean_of(out, 3, W / 2 - 2, W / 2), right = mean_of(out, 3, W / 2, W / 2 + 2);
    print_message("fold: the columns beside it %.4f | %.4f (truth 0.05 | 0.6)\n", left, right);
    assert_true(fabs(left - 0.05) < 0.05 * 0.2);
    assert_true(fabs(right - 0.6) < 0.6 * 0.05);
    assert_true(rmse_of(out, 3, truth, 0, W) < rmse_of(px, 3 + G, truth, 0, W) / 3);
    free(px), free(out);
}

/* a checker of albedos 0.2 and 0.9 under even light, no noise: the light
 * divided by the albedo is flat, so each texel comes back as it was */
static void a_texture_keeps_its_detail(void **state)
{
    (void)state;
    uint8_t *px = malloc((size_t)W * H * (3 + G));
    assert_non_null(px);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const real a = ((x / 2 + y / 2) & 1) ? R(0.9) : R(0.2);
            double c[3] = {0.7 * (double)a, 0.7 * (double)a, 0.7 * (double)a};
            put(px + ((size_t)y * W + (size_t)x) * (3 + G), c, v3_splat(a), v3(0, 0, 1), R(3), 1);
        }
    uint8_t *out = denoised(px, W, H, 3, NULL);
    int worst = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        const int d = abs((int)out[3 * i] - (int)px[i * (3 + G)]);
        worst = d > worst ? d : worst;
    }
    print_message("checker: largest change %d codes\n", worst);
    assert_true(worst <= 1);
    free(px), free(out);
}

static void a_firefly_is_cut(void **state)
{
    (void)state;
    uint8_t *px = two_walls(W, 0.02, 0.02, 0.2, NULL);
    const size_t at = (size_t)(H / 2) * W + W / 2;
    double c[3] = {1, 1, 1}; /* fifty times its neighbours */
    put(px + at * (3 + G), c, v3_splat(R(0.8)), v3(0, 0, 1), R(5), 1);
    uint8_t *out = denoised(px, W, H, 3, NULL);
    print_message("firefly: %.4f -> %.4f\n", (double)srgb_decode8[255], (double)srgb_decode8[out[3 * at]]);
    assert_true(srgb_decode8[out[3 * at]] < 0.1f);
    free(px), free(out);
}

/* a 2 x 2 highlight of 0.8 on a wall of 0.2 (a little noise): where each
 * pixel's 16 samples agree within 1%, it stays (the spread of its
 * neighbours' light is the picture's, not noise); of one sample a pixel
 * (its noise unknown), the first pass spreads it */
static void a_highlight_whose_samples_agree_stays(void **state)
{
    (void)state;
    double peak[2];
    for (int k = 0; k < 2; k++) {
        const int samples = k ? 1 : 16;
        uint8_t *px = malloc((size_t)W * H * (3 + G));
        assert_non_null(px);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                const size_t i = (size_t)y * W + (size_t)x;
                const int spot = x / 2 == W / 4 && y / 2 == H / 4;
                const double v = (spot ? 0.8 : 0.2) * (1 + 0.02 * noise((uint32_t)i));
                double c[3] = {v, v, v};
                put_n(px + i * (3 + G), c, v3_splat(R(0.8)), v3(0, 0, 1), R(5), 1, samples, 0.01);
            }
        uint8_t *out = denoised(px, W, H, 3, NULL);
        peak[k] = (double)srgb_decode8[out[3 * ((size_t)(H / 2) * W + W / 2)]];
        free(px), free(out);
    }
    print_message("highlight 0.8: %.4f with 16 samples that agree, %.4f with one\n", peak[0], peak[1]);
    assert_true(peak[0] > 0.75);
    assert_true(peak[1] < 0.7);
}

/* the background (no surface) passes byte for byte, and no surface pixel
 * takes its light */
static void the_background_passes(void **state)
{
    (void)state;
    uint8_t *px = two_walls(W, 0.2, 0.2, 0.5, NULL);
    for (int y = 0; y < H / 2; y++)
        for (int x = 0; x < W; x++) {
            double c[3] = {noise((uint32_t)(x + y)) * 0.5 + 0.5, 1, 0};
            put(px + ((size_t)y * W + (size_t)x) * (3 + G), c, v3_splat(R(1)), v3_splat(R(0)), R(0), 0);
        }
    uint8_t *out = denoised(px, W, H, 3, NULL);
    for (size_t i = 0; i < (size_t)W * H / 2; i++)
        assert_memory_equal(out + 3 * i, px + i * (3 + G), 3);
    for (size_t i = (size_t)W * H / 2; i < (size_t)W * H; i++)
        assert_true(out[3 * i + 1] == out[3 * i]); /* grey: no green of the sky */
    free(px), free(out);
}

static void rgbe_frames_are_filtered_in_light(void **state)
{
    (void)state;
    uint8_t *px = malloc((size_t)W * H * (4 + G));
    assert_non_null(px);
    double truth[W * H];
    for (size_t i = 0; i < (size_t)W * H; i++) {
        const double v = 40 * (1 + 0.6 * noise((uint32_t)i)); /* far beyond white */
        truth[i] = 40;
        rgbe_encode((real)v, (real)v, (real)v, px + i * (4 + G));
        Guide g = {.albedo = v3_splat(R(0.5)), .normal = v3(0, 1, 0), .depth = R(2), .surface = 1};
        denoise_guide_pack(&g, 1, v3_splat((real)v), px + i * (4 + G) + 4);
    }
    uint8_t *out = denoised(px, W, H, 4, NULL);
    double s0 = 0, s1 = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        double a[3], b[3];
        rgbe_decode(px + i * (4 + G), a);
        rgbe_decode(out + 4 * i, b);
        s0 += (a[0] - truth[i]) * (a[0] - truth[i]), s1 += (b[0] - truth[i]) * (b[0] - truth[i]);
    }
    print_message("RGBE: RMSE %.3f -> %.3f (light 40)\n", sqrt(s0 / (W * H)), sqrt(s1 / (W * H)));
    assert_true(sqrt(s1 / (W * H)) < sqrt(s0 / (W * H)) / 4);
    free(px), free(out);
}

/* every small size, finite codes; and the bytes whatever the threads */
static void any_size_any_threads(void **state)
{
    (void)state;
    const uint32_t sizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {2, 2}, {7, 3}, {33, 17}, {W, H}};
    uint8_t *px = two_walls(W / 3, 0.1, 0.7, 0.8, NULL);
    Err err;
    Pool *pool = pool_create(3, &err);
    assert_non_null(pool);
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++) {
        const uint32_t w = sizes[s][0], h = sizes[s][1];
        uint8_t *a = denoised(px, w, h, 3, NULL), *b = denoised(px, w, h, 3, pool);
        assert_memory_equal(a, b, (size_t)w * h * 3);
        free(a), free(b);
    }
    /* larger than the denoiser was made for: refused */
    Denoiser *d = denoiser_create(NULL, 2, 2);
    uint8_t out[3 * 9];
    assert_int_equal(denoise_frame(d, px, 3, 3, 3, 0, out, &err), -1);
    assert_non_null(strstr(err.msg, "larger"));
    denoiser_destroy(d);
    pool_destroy(pool);
    free(px);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(guides_come_back),
        cmocka_unit_test(any_bytes_decode_finite),
        cmocka_unit_test(a_flat_frame_is_smoothed),
        cmocka_unit_test(a_fold_stays_a_fold),
        cmocka_unit_test(a_texture_keeps_its_detail),
        cmocka_unit_test(a_firefly_is_cut),
        cmocka_unit_test(a_highlight_whose_samples_agree_stays),
        cmocka_unit_test(the_background_passes),
        cmocka_unit_test(rgbe_frames_are_filtered_in_light),
        cmocka_unit_test(any_size_any_threads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

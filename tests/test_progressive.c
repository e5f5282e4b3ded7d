/* test_progressive.c - a path-traced view's N x N samples in batches
 * (render/progressive.h): each pixel's first 4^k samples take one place in
 * every 2^(m-k) x 2^(m-k) block of its 2^m x 2^m grid (and the first
 * 2 x 4^k one in every half of such a block), so that a still frame on its
 * way is as even as a grid of its samples; the batches double the samples
 * and cover N x N once; a frame's batches, rendered apart as sums (on
 * another pool, in other segments) and added up as a server adds them,
 * give after each batch lanray-render's picture of the batches so far
 * (--still-frame) and after the last its picture at N x N, byte for byte,
 * with and without guides, in 8-bit codes and RGBE, exposed; sums that
 * are not numbers (a client's, on a server) still make finite guides; a
 * batch of a frame whose samples do not go in batches is refused. */
#include "helpers.h"

#include <math.h>
#include <stdlib.h>

#include "base/sample.h"
#include "render/render.h"
#include "scene/scene_default.h"
#include "scene/scene_fields.h"
#include "worlds.h"

static void cells_take_every_place_once(void **state)
{
    (void)state;
    for (uint32_t key = 1; key < 400; key++)
        for (int m = 1; m <= 5; m++) {
            const uint32_t n = 1u << m;
            static uint8_t seen[32][32];
            /* prefixes of 4^k (squares) and 2 x 4^k (halves of squares, either way) */
            for (int e = 0; e <= 2 * m; e++) {
                const uint32_t count = 1u << e, bx = n >> (e / 2), by = n >> ((e + 1) / 2);
                for (int turn = 0; turn < (e % 2 ? 2 : 1); turn++) {
                    memset(seen, 0, sizeof seen);
                    const SampleSobol q = sample_grid_seq(sample_hash(key));
                    for (uint32_t s = 0; s < count; s++) {
                        uint32_t i, j;
                        sample_grid_cell(&q, s, m, &i, &j);
                        assert_true(i < n && j < n);
                        const uint32_t a = turn ? j : i, b = turn ? i : j;
                        if (seen[a / bx][b / by]++)
                            fail_msg("key %u, %u x %u: the first %u samples put two in one block of %u x %u", key, n,
                                     n, count, bx, by);
                    }
                }
            }
        }
}

static void batches_double_and_cover_the_grid(void **state)
{
    (void)state;
    for (int n = 2; n <= AA_MAX; n *= 2) {
        RenderSettings rs = {.aa = n, .integrator = INTEGRATOR_PATH};
        const int batches = progressive_batches(&rs);
        assert_int_equal(1u << (batches - 1), (uint32_t)(n * n));
        assert_true(batches <= PROG_MAX_BATCHES);
        uint32_t next = 0;
        for (int b = 1; b <= batches; b++) {
            assert_int_equal(progressive_start(b), next);
            assert_true(progressive_end(b) > next);
            for (uint32_t s = next; s < progressive_end(b); s++)
                assert_int_equal(progressive_last(s), s + 1 == progressive_end(b));
            next = progressive_end(b);
            /* from the second on, as many as all before */
            if (b > 1)
                assert_int_equal(progressive_end(b) - progressive_start(b), progressive_start(b));
        }
        assert_int_equal(next, (uint32_t)(n * n));
    }
    const RenderSettings whitted = {.aa = 4}, three = {.aa = 3, .integrator = INTEGRATOR_PATH},
                         adaptive = {.aa = 4, .adaptive = 1, .integrator = INTEGRATOR_PATH},
                         one = {.aa = 1, .integrator = INTEGRATOR_PATH};
    assert_int_equal(progressive_batches(&whitted), 0);
    assert_int_equal(progressive_batches(&three), 0);
    assert_int_equal(progressive_batches(&adaptive), 0);
    assert_int_equal(progressive_batches(&one), 0);
}

/* the frame of s's view rendered whole by p (batches: the first `batches`, 0 all) */
static uint8_t *render_whole(RenderPool *p, Scene *s, int w, int h, int batches)
{
    s->settings.batch = 0;
    s->settings.batches = batches;
    const uint32_t bpp = render_pixel_bytes(&s->settings);
    uint8_t *px = malloc((size_t)w * h * bpp);
    Err err;
    if (render_span(p, world_now(s), w, h, 0, (uint64_t)w * h, px, NULL, NULL, &err))
        fail_msg("%s", err.msg);
    s->settings.batches = 0;
    return px;
}

/* batch b's sums of every pixel, rendered by p in segments of `seg` pixels */
static uint8_t *render_batch(RenderPool *p, Scene *s, int w, int h, int b, uint64_t seg)
{
    s->settings.batch = b;
    const uint32_t bpp = render_pixel_bytes(&s->settings);
    const uint64_t n = (uint64_t)w * h;
    uint8_t *px = malloc(n * bpp);
    const World *world = world_now(s);
    Err err;
    for (uint64_t a = 0; a < n; a += seg)
        if (render_span(p, world, w, h, a, a + seg <= n ? seg : n - a, px + a * bpp, NULL, NULL, &err))
            fail_msg("%s", err.msg);
    s->settings.batch = 0;
    return px;
}

static void batches_add_up_to_the_picture(void **state)
{
    (void)state;
    Scene *s;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Err err;
    if (scene_default(&s, &opt, &err))
        fail_msg("%s", err.msg);
    RenderPool *one = render_pool_create(1, &err), *three = render_pool_create(3, &err);
    const int W = 23, H = 17;
    const size_t n = (size_t)W * H;
    s->settings.integrator = INTEGRATOR_PATH;
    s->settings.adaptive = 0;
    s->settings.depth = 3;
    for (int mode = 0; mode < 3; mode++) {
        s->settings.aa = mode == 2 ? 2 : 4;
        s->settings.denoise = mode >= 1;
        s->settings.hdr = mode == 2;
        s->settings.exposure = mode == 0 ? R(0.5) : R(0);
        const int batches = progressive_batches(&s->settings);
        const uint32_t bpp = render_pixel_bytes(&s->settings), reals = progressive_reals(&s->settings);
        s->settings.batch = 1;
        assert_int_equal(render_pixel_bytes(&s->settings), reals * sizeof(real));
        s->settings.batch = 0;
        real *acc = calloc(n * reals, sizeof(real));
        uint8_t *shown = malloc(n * bpp), *before = calloc(n, bpp);
        for (int b = 1; b <= batches; b++) {
            uint8_t *sums = render_batch(b % 2 ? three : one, s, W, H, b, b % 2 ? 7 : n);
            s->settings.batch = b;
            /* a server shows a batch's segments as they come (peeked) with
             * the sums before, unchanged, and adds the whole batch after */
            real *kept = malloc(n * reals * sizeof(real));
            memcpy(kept, acc, n * reals * sizeof(real));
            uint8_t *peeked = malloc(n * bpp);
            for (size_t a = 0; a < n; a += 7)
                progressive_frame_peek(&s->settings, b == 1 ? NULL : acc + a * reals, sums + a * reals * sizeof(real),
                                       n - a < 7 ? n - a : 7, peeked + a * bpp);
            assert_memory_equal(acc, kept, n * reals * sizeof(real));
            progressive_frame_add(&s->settings, acc, sums, n, shown);
            assert_memory_equal(peeked, shown, n * bpp);
            free(kept);
            free(peeked);
            s->settings.batch = 0;
            uint8_t *ref = render_whole(one, s, W, H, b);
            assert_memory_equal(shown, ref, n * bpp);
            if (b > 1) /* a batch changes the picture: the comparison can fail */
                assert_memory_not_equal(shown, before, n * bpp);
            memcpy(before, shown, n * bpp);
            free(ref);
            free(sums);
        }
        uint8_t *whole = render_whole(three, s, W, H, 0);
        assert_memory_equal(shown, whole, n * bpp);
        free(whole);
        free(acc);
        free(shown);
        free(before);
    }
    render_pool_destroy(one);
    render_pool_destroy(three);
    scene_destroy(s);
}

/* A client's sums may say anything: the pixels a server makes of them are
 * codes and guides the filter reads as finite numbers. */
static void any_sums_make_a_pixel(void **state)
{
    (void)state;
    const real odd[] = {NAN, INFINITY, -INFINITY, R(1e30), R(-1e30), R(-1), R(0), R(3e38), R(5)};
    const int k = (int)(sizeof odd / sizeof *odd);
    enum { N = 300 };
    uint8_t sums[N * PROG_MAX * sizeof(real)];
    for (int i = 0; i < N; i++)
        for (uint32_t c = 0; c < PROG_MAX; c++) {
            const real v = odd[(i * 7 + (int)c * 3 + i / k) % k];
            memcpy(sums + (i * PROG_MAX + c) * sizeof(real), &v, sizeof v);
        }
    for (int hdr = 0; hdr < 2; hdr++) {
        const RenderSettings rs = {.aa = 4, .integrator = INTEGRATOR_PATH, .denoise = 1, .hdr = hdr, .batch = 3};
        real acc[N * PROG_MAX] = {0};
        uint8_t out[N * (4 + DENOISE_GUIDE_BYTES)];
        const uint32_t bpp = (hdr ? 4u : 3u) + DENOISE_GUIDE_BYTES;
        progressive_frame_add(&rs, acc, sums, N, out);
        for (int i = 0; i < N; i++) {
            float albedo[3], normal[3], depth, noise;
            denoise_guide_unpack(out + i * bpp + (hdr ? 4 : 3), albedo, normal, &depth, &noise);
            for (int c = 0; c < 3; c++)
                assert_true(isfinite(albedo[c]) && isfinite(normal[c]));
            assert_true(isfinite(depth) && depth >= 0 && isfinite(noise));
        }
    }
    /* a surface count past the samples is all of them; a normal that is
     * not a number is none (the pixel's own distance kept); all of it not
     * a number, no surface */
    const RenderSettings rs = {.aa = 2, .integrator = INTEGRATOR_PATH, .denoise = 1, .batch = 3}; /* 4 samples */
    const real a[2][PROG_MAX] = {{1, 1, 1, 2, 2, 2, 4, INFINITY, NAN, 0, R(5), R(1e30)},
                                 {NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN}};
    real acc[2 * PROG_MAX] = {0};
    enum { PX = 3 + DENOISE_GUIDE_BYTES };
    uint8_t out[2 * PX];
    progressive_frame_add(&rs, acc, (const uint8_t *)a, 2, out);
    float albedo[3], normal[3], depth, noise;
    denoise_guide_unpack(out + 3, albedo, normal, &depth, &noise);
    assert_float_equal(depth, 1.25, 1e-3); /* 5 over 4 samples */
    assert_float_equal(albedo[0], 0.5, 0.01);
    assert_int_equal(denoise_guide_instance(out + 3), 0); /* sums carry no instance */
    denoise_guide_unpack(out + PX + 3, albedo, normal, &depth, &noise);
    assert_true(depth == 0 && albedo[0] == 0);
}

static void batches_of_other_frames_refused(void **state)
{
    (void)state;
    Scene *s;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    assert_int_equal(scene_default(&s, &opt, NULL), 0);
    char why[200];
    RenderSettings rs = s->settings;
    rs.integrator = INTEGRATOR_PATH, rs.aa = 4, rs.adaptive = 0, rs.batch = 5;
    assert_null(settings_problem(&rs, why, sizeof why));
    rs.batch = 6; /* 4 x 4 takes 5 */
    assert_non_null(settings_problem(&rs, why, sizeof why));
    assert_contains(why, "batch 6");
    const RenderSettings bad[] = {
        {.aa = 4, .batch = 1},
        {.aa = 3, .batch = 1, .integrator = INTEGRATOR_PATH},
        {.aa = 4, .adaptive = 1, .batch = 1, .integrator = INTEGRATOR_PATH},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        rs = s->settings;
        rs.aa = bad[i].aa, rs.adaptive = bad[i].adaptive, rs.batch = bad[i].batch, rs.integrator = bad[i].integrator;
        assert_non_null(settings_problem(&rs, why, sizeof why));
        assert_contains(why, "not path-traced on a regular grid");
    }
    /* and the renderer refuses the picture of batches a frame does not have */
    RenderPool *p = render_pool_create(1, NULL);
    s->settings.integrator = INTEGRATOR_PATH, s->settings.aa = 3, s->settings.adaptive = 0, s->settings.batches = 1;
    uint8_t px[4 * 4 * 3];
    Err err = {{0}};
    assert_int_equal(render_span(p, world_now(s), 4, 4, 0, 16, px, NULL, NULL, &err), -1);
    assert_contains(err.msg, "do not go in batches");
    s->settings.aa = 2, s->settings.batches = 4; /* 2 x 2 takes 3 */
    assert_int_equal(render_span(p, world_now(s), 4, 4, 0, 16, px, NULL, NULL, &err), -1);
    assert_contains(err.msg, "batch 4 of 3");
    render_pool_destroy(p);
    scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cells_take_every_place_once),
        cmocka_unit_test(batches_double_and_cover_the_grid),
        cmocka_unit_test(batches_add_up_to_the_picture),
        cmocka_unit_test(any_sums_make_a_pixel),
        cmocka_unit_test(batches_of_other_frames_refused),
    };
    int rc = cmocka_run_group_tests_name("progressive", tests, NULL, NULL);
    world_now_free();
    return rc;
}

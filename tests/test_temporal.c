/* test_temporal.c - a path-traced view's moving frames added up by a
 * reprojected history (render/temporal.h), on frames made here: a striped
 * wall seen by a camera that slides along it, each frame's light the
 * stripes' plus noise.  After a dozen frames each pixel is as close to its
 * stripe's light as some eight frames' mean would be (the history follows
 * the wall across the pixels; a history that did not, or that was not
 * there, is several times further off), in 8-bit codes and in RGBE, and
 * with frames of two render scales in turn; a
 * surface that comes into view (another distance, another way) starts
 * again from its own bytes, as does every pixel after a new epoch, and a
 * wall that comes out from behind a moving edge is not the edge's light,
 * and a lamp's edge (no distance in its guide) adds up anti-aliased; a still
 * frame with fewer samples than the history is weighed with it and one
 * with as many is its own bytes; a Whitted view's history, held within
 * each frame's own light, lets a highlight that moved with the view go
 * and still adds the noise up; the bytes are the same on any threads,
 * and a frame larger than the history is refused untouched. */
#include "helpers.h"

#include <math.h>
#include <stdlib.h>

#include "base/sample.h"
#include "base/srgb.h"
#include "render/denoise.h"
#include "render/temporal.h"

enum { W = 64, H = 48 };
#define WALL_Z R(-10)

/* The stripes' light at x along the wall. */
static real stripes(real x) { return R(0.25) + R(0.15) * sin(x * R(3)); }

/* A frame of the wall at distance z (its normal nz: 1 faces the camera)
 * through camera c: its pixels (colour_bytes of colour, then the guide),
 * each the stripes' light plus noise of +-amp (drawn from the frame's
 * number and the pixel), and the light without noise into truth; the
 * wall moved `shift` along x, its guides naming instance inst (0: none). */
static void wall_frame_moved(const Camera *c, int w, int h, real z, real nz, uint32_t frame, real amp, uint32_t cb,
                             real shift, uint32_t inst, uint8_t *px, real *truth)
{
    CameraFrame cf = camera_frame(c, w, h);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            vec3 o, d;
            camera_ray(&cf, (real)x + R(0.5), (real)y + R(0.5), &o, &d);
            const real t = (z - o.z) / d.z;
            const real l = stripes(o.x + d.x * t - shift);
            const uint32_t key = sample_mix(sample_hash(frame), (uint32_t)(y * w + x));
            const real v = l + amp * (R(2) * sample_unit(key) - R(1));
            uint8_t *p = px + (size_t)(y * w + x) * (cb + DENOISE_GUIDE_BYTES);
            if (cb == 4)
                rgbe_encode(v, v, v, p);
            else
                for (int k = 0; k < 3; k++)
                    p[k] = srgb_encode8(v);
            const Guide g = {v3(R(0.8), R(0.8), R(0.8)), v3(R(0), sqrt(R(1) - nz * nz), nz), t, 1, v * v, inst};
            denoise_guide_pack(&g, 1, v3(v, v, v), p + cb);
            if (truth)
                truth[y * w + x] = l;
        }
}

static void wall_frame_at(const Camera *c, int w, int h, real z, real nz, uint32_t frame, real amp, uint32_t cb,
                          uint8_t *px, real *truth)
{
    wall_frame_moved(c, w, h, z, nz, frame, amp, cb, R(0), 0, px, truth);
}

/* ... at the full size */
static void wall_frame(const Camera *c, real z, real nz, uint32_t frame, real amp, uint32_t cb, uint8_t *px,
                       real *truth)
{
    wall_frame_at(c, W, H, z, nz, frame, amp, cb, px, truth);
}

/* A pixel's light as its colour bytes say. */
static real light_of(const uint8_t *p, uint32_t cb)
{
    if (cb == 4) {
        double v[3];
        rgbe_decode(p, v);
        return (real)v[1];
    }
    return (real)srgb_decode8[p[1]];
}

/* The RMS of a frame's light against truth. */
static real rms_off(const uint8_t *px, uint32_t cb, const real *truth)
{
    double sum = 0;
    for (int i = 0; i < W * H; i++) {
        const double e = (double)(light_of(px + (size_t)i * (cb + DENOISE_GUIDE_BYTES), cb) - truth[i]);
        sum += e * e;
    }
    return (real)sqrt(sum / (W * H));
}

static Camera slide(int i) { return camera_from_angles(v3(R(0.04) * (real)i, R(0), R(0)), 0, 0, 0, R(1.2)); }

/* Frames 0 .. n - 1 of the sliding camera through t (epoch 1); the last
 * frame's pixels (as the history showed them) and truth left in px, truth. */
static void fly(Temporal *t, int n, uint32_t cb, uint8_t *px, real *truth)
{
    for (int i = 0; i < n; i++) {
        const Camera c = slide(i);
        wall_frame(&c, WALL_Z, R(1), (uint32_t)i, R(0.1), cb, px, truth);
        const TemporalFrame f = {c, 1, 1, 0, 0, NULL, 0};
        assert_int_equal(temporal_add(t, px, W, H, cb, 0, &f), 0);
    }
}

static void history_follows_the_wall(void **state)
{
    (void)state;
    for (uint32_t cb = 3; cb <= 4; cb++) {
        uint8_t *px = malloc((size_t)W * H * (cb + DENOISE_GUIDE_BYTES));
        real *truth = malloc(sizeof(real) * W * H);
        Temporal *t = temporal_create(NULL, W, H, 8);
        assert_non_null(t);
        /* one frame alone: its noise (uniform +-0.1: RMS 0.058) */
        const Camera c11 = slide(11);
        wall_frame(&c11, WALL_Z, R(1), 11, R(0.1), cb, px, truth);
        const real alone = rms_off(px, cb, truth);
        fly(t, 12, cb, px, truth);
        const real added = rms_off(px, cb, truth);
        print_message("%u-byte colour: RMS %.4f one frame, %.4f after 12 through the history\n", cb, (double)alone,
                      (double)added);
        assert_true(alone > R(0.04));
        assert_true(added < alone * R(0.5));
        /* a history that stays where the pixels are (the camera said not to
         * move) smears the stripes: much further off */
        Temporal *fixed = temporal_create(NULL, W, H, 8);
        for (int i = 0; i < 12; i++) {
            const Camera c = slide(i), still = slide(0);
            wall_frame(&c, WALL_Z, R(1), (uint32_t)i, R(0.1), cb, px, truth);
            const TemporalFrame f = {still, 1, 1, 0, 0, NULL, 0};
            temporal_add(fixed, px, W, H, cb, 0, &f);
        }
        assert_true(rms_off(px, cb, truth) > added * R(2));
        temporal_destroy(fixed);
        temporal_destroy(t);
        free(px);
        free(truth);
    }
}

/* Frames at render scales 1 and 2 in turn (64 x 48 and 32 x 24, as a
 * window's pace may pick them): the history follows the wall from one
 * size to the other, and the full-size frame after a dozen is closer to
 * the stripes than one alone. */
static void render_scales_alternate(void **state)
{
    (void)state;
    uint8_t *px = malloc((size_t)W * H * (3 + DENOISE_GUIDE_BYTES));
    real *truth = malloc(sizeof(real) * W * H);
    Temporal *t = temporal_create(NULL, W, H, 4);
    const Camera c12 = slide(12);
    wall_frame(&c12, WALL_Z, R(1), 12, R(0.1), 3, px, truth);
    const real alone = rms_off(px, 3, truth);
    for (int i = 0; i <= 12; i++) {
        const int k = i % 2 ? 2 : 1;
        const Camera c = slide(i);
        wall_frame_at(&c, W / k, H / k, WALL_Z, R(1), (uint32_t)i, R(0.1), 3, px, k == 1 ? truth : NULL);
        const TemporalFrame f = {c, 1, 1, 0, 0, NULL, 0};
        assert_int_equal(temporal_add(t, px, (uint32_t)(W / k), (uint32_t)(H / k), 3, 0, &f), 0);
    }
    const real added = rms_off(px, 3, truth);
    print_message("scales 1 and 2 in turn: RMS %.4f, one frame %.4f\n", (double)added, (double)alone);
    assert_true(added < alone * R(0.75));
    temporal_destroy(t);
    free(px);
    free(truth);
}

/* Whether every pixel of a is b's. */
static int same_bytes(const uint8_t *a, const uint8_t *b, size_t n) { return memcmp(a, b, n) == 0; }

static void new_surfaces_start_again(void **state)
{
    (void)state;
    const size_t bytes = (size_t)W * H * (3 + DENOISE_GUIDE_BYTES);
    uint8_t *px = malloc(bytes), *own = malloc(bytes);
    Temporal *t = temporal_create(NULL, W, H, 8);
    fly(t, 6, 3, px, NULL);
    /* the next frame sees a wall half as far (a surface come into view),
     * then one facing another way: each pixel its own bytes */
    const Camera c = slide(6);
    const real zs[2] = {R(-5), WALL_Z}, ns[2] = {R(1), R(0.7)};
    for (int k = 0; k < 2; k++) {
        wall_frame(&c, zs[k], ns[k], 100 + (uint32_t)k, R(0.1), 3, own, NULL);
        memcpy(px, own, bytes);
        const TemporalFrame f = {c, 1, 1, 0, 0, NULL, 0};
        temporal_add(t, px, W, H, 3, 0, &f);
        assert_true(same_bytes(px, own, bytes));
        fly(t, 4, 3, px, NULL); /* history again */
    }
    /* the same wall again, a frame on: added up (not its own bytes) */
    const Camera c4 = slide(4);
    wall_frame(&c4, WALL_Z, R(1), 200, R(0.1), 3, own, NULL);
    memcpy(px, own, bytes);
    TemporalFrame f = {c4, 1, 1, 0, 0, NULL, 0};
    temporal_add(t, px, W, H, 3, 0, &f);
    assert_false(same_bytes(px, own, bytes));
    /* ... but under a new epoch (a scene or settings changed) it is */
    memcpy(px, own, bytes);
    f.epoch = 2;
    temporal_add(t, px, W, H, 3, 0, &f);
    assert_true(same_bytes(px, own, bytes));
    temporal_destroy(t);
    free(px);
    free(own);
}

/* A dark board before the wall, its edge at x = 0, the camera sliding
 * right: the wall comes out from behind the edge.  A frame of it (the
 * board's light 0.05, the wall's 0.5, noise +-0.1) into px, and per pixel
 * whether it saw the board.  lamp: the board is a lamp in the wall's plane
 * instead (light 0.9, no noise, and as an emitter no distance in its
 * guide). */
static void board_frame(const Camera *c, uint32_t frame, uint8_t *px, uint8_t *board, int lamp)
{
    CameraFrame cf = camera_frame(c, W, H);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            vec3 o, d;
            camera_ray(&cf, (real)x + R(0.5), (real)y + R(0.5), &o, &d);
            const real tb = ((lamp ? WALL_Z : R(-5)) - o.z) / d.z, tw = (WALL_Z - o.z) / d.z;
            const int on = o.x + d.x * tb < R(0);
            const real l = on ? (lamp ? R(0.9) : R(0.05)) : R(0.5), t = on ? tb : tw;
            const real noise = on && lamp ? R(0) : R(0.1);
            const real v = l + noise * (R(2) * sample_unit(sample_mix(sample_hash(frame), (uint32_t)(y * W + x))) - R(1));
            uint8_t *p = px + (size_t)(y * W + x) * (3 + DENOISE_GUIDE_BYTES);
            for (int k = 0; k < 3; k++)
                p[k] = srgb_encode8(v);
            const Guide g = {v3(R(0.8), R(0.8), R(0.8)), v3(R(0), R(0), R(1)), t, on && lamp ? 0 : 1, v * v, 0};
            denoise_guide_pack(&g, 1, v3(v, v, v), p + 3);
            board[y * W + x] = (uint8_t)on;
        }
}

/* Frame i of the board (or lamp) as the camera slides right by `step` a
 * frame, added to t. */
static void board_step(Temporal *t, int i, real step, int lamp, uint8_t *px, uint8_t *board)
{
    const Camera c = camera_from_angles(v3(step * (real)i, R(0), R(0)), 0, 0, 0, R(1.2));
    board_frame(&c, (uint32_t)i, px, board, lamp);
    const TemporalFrame f = {c, 1, 1, 0, 0, NULL, 0};
    assert_int_equal(temporal_add(t, px, W, H, 3, 0, &f), 0);
}

/* The wall that comes out from behind the board's edge is the wall's light
 * at once, not the board's that stood there the frame before (a dark
 * trail beside every edge that moves). */
static void what_comes_out_is_not_what_hid_it(void **state)
{
    (void)state;
    uint8_t *px = malloc((size_t)W * H * (3 + DENOISE_GUIDE_BYTES)), before[W * H], now[W * H];
    Temporal *t = temporal_create(NULL, W, H, 8);
    int revealed = 0;
    for (int i = 0; i < 10; i++) {
        board_step(t, i, R(0.08), 0, px, now);
        for (int p = 0; i > 0 && p < W * H; p++)
            if (before[p] && !now[p]) { /* board the frame before, wall now */
                assert_true(light_of(px + (size_t)p * (3 + DENOISE_GUIDE_BYTES), 3) > R(0.38));
                revealed++;
            }
        memcpy(before, now, sizeof now);
    }
    assert_true(revealed > 20);
    temporal_destroy(t);
    free(px);
}

/* A lamp's edge (its pixels no distance, as an emitter's): the pixels it
 * crosses as the camera slides add up lamp and wall, anti-aliased, where
 * each was one or the other, as its own frame said. */
static void a_lamp_edge_adds_up(void **state)
{
    (void)state;
    uint8_t *px = malloc((size_t)W * H * (3 + DENOISE_GUIDE_BYTES)), lamp[W * H];
    Temporal *t = temporal_create(NULL, W, H, 8);
    int between = 0;
    for (int i = 0; i < 10; i++)
        board_step(t, i, R(0.031), 1, px, lamp);
    for (int p = 0; p < W * H; p++) {
        const real l = light_of(px + (size_t)p * (3 + DENOISE_GUIDE_BYTES), 3);
        if (lamp[p]) /* the lamp's own pixels: its light, or on its edge less */
            assert_true(l <= R(0.91));
        between += l > R(0.65) && l < R(0.85);
    }
    print_message("%d pixels between lamp and wall\n", between);
    assert_true(between >= H / 2);
    temporal_destroy(t);
    free(px);
}

/* A Whitted view's history (TemporalFrame clip): a highlight fixed on
 * the screen while the wall slides (it moves with the view, as a
 * highlight does over a surface) that then goes is gone from the next
 * frame where the history is held within the frame's own light about
 * each pixel, and lingers where it is not; the noise still adds up. */
static void the_clip_lets_a_moved_highlight_go(void **state)
{
    (void)state;
    const uint32_t cb = 3, bpp = cb + DENOISE_GUIDE_BYTES;
    uint8_t *px = malloc((size_t)W * H * bpp);
    real *truth = malloc(sizeof(real) * W * H);
    real left[2];
    for (int clip = 0; clip <= 1; clip++) {
        Temporal *t = temporal_create(NULL, W, H, 2);
        for (int i = 0; i < 7; i++) {
            const Camera c = slide(i);
            wall_frame(&c, WALL_Z, R(1), (uint32_t)i, R(0), cb, px, truth);
            for (int y = 0; i < 6 && y < H; y++) /* columns 20 to 27 brighter by 0.5 while it shines */
                for (int x = 20; x < 28; x++)
                    for (int k = 0; k < 3; k++)
                        px[(size_t)(y * W + x) * bpp + k] = srgb_encode8(truth[y * W + x] + R(0.5));
            const TemporalFrame f = {c, 1, 1, 0, clip, NULL, 0};
            assert_int_equal(temporal_add(t, px, W, H, cb, 0, &f), 0);
        }
        real most = 0;
        for (int y = 0; y < H; y++)
            for (int x = 16; x < 32; x++) {
                const real e = fabs(light_of(px + (size_t)(y * W + x) * bpp, cb) - truth[y * W + x]);
                most = e > most ? e : most;
            }
        left[clip] = most;
        temporal_destroy(t);
    }
    print_message("the highlight's most left a frame after it went: %.3f, clipped %.3f\n", (double)left[0],
                  (double)left[1]);
    /* clipped, what is left is within the stripes' own change over 3 x 3
     * pixels (up to 0.12) */
    assert_true(left[0] > R(0.15));
    assert_true(left[1] < left[0] / R(3));
    /* noise of +-0.1 a frame: a dozen frames through a clipped history of 2
     * come closer than one alone */
    Temporal *t = temporal_create(NULL, W, H, 2);
    const Camera c11 = slide(11);
    wall_frame(&c11, WALL_Z, R(1), 11, R(0.1), cb, px, truth);
    const real alone = rms_off(px, cb, truth);
    for (int i = 0; i < 12; i++) {
        const Camera c = slide(i);
        wall_frame(&c, WALL_Z, R(1), (uint32_t)i, R(0.1), cb, px, truth);
        const TemporalFrame f = {c, 1, 1, 0, 1, NULL, 0};
        temporal_add(t, px, W, H, cb, 0, &f);
    }
    const real added = rms_off(px, cb, truth);
    print_message("noise: RMS %.4f one frame, %.4f through a clipped history of 2\n", (double)alone, (double)added);
    assert_true(added < alone * R(0.85));
    temporal_destroy(t);
    free(px);
    free(truth);
}

static void still_frames_take_over(void **state)
{
    (void)state;
    const size_t bytes = (size_t)W * H * (3 + DENOISE_GUIDE_BYTES);
    uint8_t *px = malloc(bytes), *own = malloc(bytes);
    real *truth = malloc(sizeof(real) * W * H);
    Temporal *t = temporal_create(NULL, W, H, 8);
    fly(t, 12, 3, px, NULL);
    const Camera c = slide(11); /* the last moving frame's */
    /* still frames of 1, 2, 4 and 8 samples (less noise each): the first
     * three weighed with the history, which they read each alike (a still
     * frame of 1 sample is as close as the history, not as one frame),
     * the last its own bytes */
    const int samples[4] = {1, 2, 4, 8};
    for (int k = 0; k < 4; k++) {
        wall_frame(&c, WALL_Z, R(1), 300 + (uint32_t)k, R(0.1) / sqrt((real)samples[k]), 3, own, truth);
        memcpy(px, own, bytes);
        const TemporalFrame f = {c, 1, samples[k], 1, 0, NULL, 0};
        temporal_add(t, px, W, H, 3, 0, &f);
        if (k < 3) {
            assert_false(same_bytes(px, own, bytes));
            assert_true(rms_off(px, 3, truth) < rms_off(own, 3, truth));
        } else {
            assert_true(same_bytes(px, own, bytes));
        }
    }
    temporal_destroy(t);
    free(px);
    free(own);
    free(truth);
}

/* The wall as a model's instance that slides along x (0.04 a frame) before
 * a still camera: where each pixel's guide names the instance and the
 * frames say where it was placed, the history follows the wall's own
 * motion (as close to the stripes as the sliding camera's history);
 * without the placements it looks where the wall was not, and is further
 * off; a pixel that names no instance stays where it was. */
static void history_follows_a_moving_instance(void **state)
{
    (void)state;
    uint8_t *px = malloc((size_t)W * H * (3 + DENOISE_GUIDE_BYTES));
    real *truth = malloc(sizeof(real) * W * H);
    const Camera c = slide(0);
    real off[2];
    for (int placed = 0; placed < 2; placed++) {
        Temporal *t = temporal_create(NULL, W, H, 8);
        assert_non_null(t);
        for (int i = 0; i < 12; i++) {
            const real shift = R(0.04) * (real)i;
            wall_frame_moved(&c, W, H, WALL_Z, R(1), (uint32_t)i, R(0.1), 3, shift, 1, px, truth);
            const Instance in = {0, v3(shift, R(0), R(0)), v3(R(0), R(0), R(0)), R(1), -1};
            const TemporalFrame f = {c, 1, 1, 0, 0, placed ? &in : NULL, placed ? 1u : 0u};
            assert_int_equal(temporal_add(t, px, W, H, 3, 0, &f), 0);
        }
        off[placed] = rms_off(px, 3, truth);
        temporal_destroy(t);
    }
    print_message("a sliding instance: RMS %.4f followed, %.4f not\n", (double)off[1], (double)off[0]);
    assert_true(off[1] < R(0.03));
    assert_true(off[0] > R(1.5) * off[1]);
    free(px);
    free(truth);
}

static void same_bytes_on_any_threads(void **state)
{
    (void)state;
    const size_t bytes = (size_t)W * H * (4 + DENOISE_GUIDE_BYTES);
    uint8_t *a = malloc(bytes), *b = malloc(bytes);
    Err err;
    Pool *pool = pool_create(3, &err);
    assert_non_null(pool);
    Temporal *alone = temporal_create(NULL, W, H, 8), *three = temporal_create(pool, W, H, 8);
    fly(alone, 9, 4, a, NULL);
    fly(three, 9, 4, b, NULL);
    assert_true(same_bytes(a, b, bytes));
    /* a frame larger than the history: refused, untouched */
    Temporal *small = temporal_create(NULL, W / 2, H, 8);
    memcpy(b, a, bytes);
    const TemporalFrame f = {slide(0), 1, 1, 0, 0, NULL, 0};
    assert_int_equal(temporal_add(small, b, W, H, 4, 0, &f), -1);
    assert_true(same_bytes(a, b, bytes));
    assert_null(temporal_create(NULL, W, H, 0));
    assert_null(temporal_create(NULL, W, H, TEMPORAL_MAX_FRAMES + 1));
    temporal_destroy(small);
    temporal_destroy(alone);
    temporal_destroy(three);
    pool_destroy(pool);
    free(a);
    free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(history_follows_the_wall),
        cmocka_unit_test(render_scales_alternate),
        cmocka_unit_test(new_surfaces_start_again),
        cmocka_unit_test(what_comes_out_is_not_what_hid_it),
        cmocka_unit_test(a_lamp_edge_adds_up),
        cmocka_unit_test(the_clip_lets_a_moved_highlight_go),
        cmocka_unit_test(still_frames_take_over),
        cmocka_unit_test(history_follows_a_moving_instance),
        cmocka_unit_test(same_bytes_on_any_threads),
    };
    return cmocka_run_group_tests_name("temporal", tests, NULL, NULL);
}

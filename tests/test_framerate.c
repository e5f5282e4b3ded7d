/* test_framerate.c - the window's frame rate (server/framerate.c), fed
 * made-up frame times: still frames slower than a second's half read
 * steadily (counted over each half second they read 0 and 2 fps in turn),
 * moving frames that jitter read their mean, a change of pace shows within
 * a second, a late frame (the last still one, a farm that stops) lowers
 * the rate as it waits, and more frames in a second than
 * the meter keeps still read their rate. */
#include "helpers.h"

#include <math.h>

#include "framerate.h"

/* Every reading from t0 to t1 in steps of 0.01 s of frames shown every
 * `interval` s from 0 on, within `tol` (relative) of 1 / interval. */
static void readings_steady(double interval, double t0, double t1, double tol)
{
    FrameRate r = {0};
    double next = 0;
    for (double now = 0; now <= t1; now += 0.01) {
        while (next <= now) {
            framerate_add(&r, next);
            next += interval;
        }
        if (now >= t0) {
            const double fps = framerate_get(&r, now);
            if (fabs(fps * interval - 1) > tol)
                fail_msg("at %.2f s: %.3f fps, frames every %.4f s", now, fps, interval);
        }
    }
}

static void still_frames_read_steadily(void **state)
{
    (void)state;
    readings_steady(0.6716, 1.5, 12, 1e-9); /* the default scene's refining still frames */
    readings_steady(2.5, 5.5, 30, 1e-9);    /* a path-traced view's */
    readings_steady(1.0 / 60, 0.1, 5, 1e-6);
}

static void jitter_reads_the_mean(void **state)
{
    (void)state;
    FrameRate r = {0};
    double t = 0;
    for (int i = 0; i < 200; i++) { /* 18 fps: 45 and 66 ms in turn */
        t += i % 2 ? 0.045 : 0.066;
        framerate_add(&r, t);
        if (t > 1.5)
            assert_true(fabs(framerate_get(&r, t + 0.01) - 2 / 0.111) < 0.05 * 2 / 0.111);
    }
}

static void a_change_shows_within_a_second(void **state)
{
    (void)state;
    FrameRate r = {0};
    double t = 0;
    for (int i = 0; i < 60; i++)
        framerate_add(&r, t += 1.0 / 30);
    assert_true(fabs(framerate_get(&r, t) - 30) < 0.01);
    for (int i = 0; i < 11; i++)
        framerate_add(&r, t += 0.1);
    assert_true(fabs(framerate_get(&r, t) - 10) < 0.01);
}

static void a_late_frame_lowers_the_rate(void **state)
{
    (void)state;
    FrameRate r = {0};
    assert_true(framerate_get(&r, 5) == 0);
    framerate_add(&r, 1);
    assert_true(framerate_get(&r, 1.5) == 0); /* one frame: no rate yet */
    double t = 1;
    for (int i = 0; i < 10; i++)
        framerate_add(&r, t += 0.6716);
    /* the last still frame takes 3 s: the rate holds for two intervals, then falls as it waits */
    assert_true(fabs(framerate_get(&r, t + 2 * 0.6716 - 0.001) - 1 / 0.6716) < 1e-9);
    assert_true(fabs(framerate_get(&r, t + 2.5) - 2 / 2.5) < 1e-9);
    framerate_add(&r, t += 3);
    assert_true(fabs(framerate_get(&r, t + 0.5) - 1 / 3.0) < 1e-9);
    /* the farm stops: 0.1 fps 20 s on, nothing in between that rises */
    double before = INFINITY;
    for (double now = t; now < t + 20; now += 0.1) {
        const double fps = framerate_get(&r, now);
        assert_true(fps <= before);
        before = fps;
    }
    assert_true(fabs(framerate_get(&r, t + 20) - 0.1) < 1e-9);
}

static void more_frames_than_kept(void **state)
{
    (void)state;
    readings_steady(1.0 / 400, 0.1, 3, 1e-6);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(still_frames_read_steadily),
        cmocka_unit_test(jitter_reads_the_mean),
        cmocka_unit_test(a_change_shows_within_a_second),
        cmocka_unit_test(a_late_frame_lowers_the_rate),
        cmocka_unit_test(more_frames_than_kept),
    };
    return cmocka_run_group_tests_name("framerate", tests, NULL, NULL);
}

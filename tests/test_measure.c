/* test_measure.c - the server's measurements (server/measure.h) against
 * hand-worked sequences: the per-segment overhead from the gaps between a
 * busy client's results, smoothed over frames; the packet CPU folded in
 * twice; frames that sent assets left out; the summary's warm-up bases. */
#include "helpers.h"

#include "measure.h"

/* one client, kept busy (it holds 2 segments at each result), results
 * `every` us apart of `render` us each, n of them in frame f */
static double busy_frame(Measure *m, MeasureClient *c, double t, uint32_t f, int n, double every, uint32_t render)
{
    for (int i = 0; i < n; i++, t += every * 1e-6) {
        measure_data(m, c, t, f, f, render, 2);
        measure_result(m, render, 1, 1);
    }
    return t;
}

static void overhead_comes_from_the_gaps(void **state)
{
    (void)state;
    Measure m = {0};
    MeasureClient c = {0};
    double work;
    /* before anything is measured: the default overhead, no work */
    assert_true(measure_frame_start(&m, 0, 1, 0, 0, 0, 1, &work) == MEASURE_OVERHEAD_US);
    assert_true(work == 0);
    /* frame 1: 5 results 1000 us apart, 800 us of rendering each: 4 gaps of 200 us */
    double t = busy_frame(&m, &c, 1.0, 1, 5, 1000, 800);
    measure_cpu(&m, 5 * 10e-6); /* 10 us of the loop's CPU per packet */
    measure_frame_end(&m, t);
    double o = measure_frame_start(&m, t, 1, 0, 0, 0, 1, &work);
    assert_float_equal(work, 5 * 800, 1e-9);                /* the frame's render time */
    assert_float_equal(m.overhead_us, 200, 1e-6);          /* the gaps' mean */
    assert_float_equal(o, 200 + 2 * 10, 1e-6);             /* plus the packet CPU twice over */
    /* frame 2: gaps of 400 us: smoothed half and half */
    t = busy_frame(&m, &c, t + 1, 2, 5, 1200, 800);
    measure_cpu(&m, 5 * 10e-6);
    measure_frame_end(&m, t);
    measure_frame_start(&m, t, 1, 0, 0, 0, 1, &work);
    assert_float_equal(m.overhead_us, 300, 1e-6);
    /* a frame that sent assets: its gaps and its CPU do not count */
    measure_asset_sent(&m, 1000);
    t = busy_frame(&m, &c, t + 1, 3, 5, 5000, 800);
    measure_cpu(&m, 1.0);
    measure_frame_end(&m, t);
    o = measure_frame_start(&m, t, 1, 0, 0, 0, 1, &work);
    assert_float_equal(m.overhead_us, 300, 1e-6);
    assert_float_equal(o, 300 + 2 * 10, 1e-6);
    /* without automatic sizing, the gaps are not folded in */
    t = busy_frame(&m, &c, t + 1, 4, 5, 2000, 800);
    measure_frame_end(&m, t);
    measure_frame_start(&m, t, 1, 0, 0, 0, 0, &work);
    assert_float_equal(m.overhead_us, 300, 1e-6);
}

static void idle_clients_and_stale_results_are_not_gaps(void **state)
{
    (void)state;
    Measure m = {0};
    MeasureClient c = {0};
    double work;
    measure_frame_start(&m, 0, 1, 0, 0, 0, 1, &work);
    /* a client that held one segment waited for the next: no gap sample */
    for (int i = 0; i < 6; i++)
        measure_data(&m, &c, 1.0 + i * 0.01, 1, 1, 800, 1);
    assert_int_equal(m.gap_samples, 0);
    /* a stale result (an older frame) counts no render time */
    measure_result(&m, 800, 0, 0);
    assert_int_equal(m.total_busy_us, 0);
    measure_result(&m, 800, 1, 0); /* a duplicate: busy, but not the frame's work */
    assert_int_equal(m.total_busy_us, 800);
    assert_int_equal(m.frame_pixels_us, 0);
}

static void warm_up_frames_set_the_bases(void **state)
{
    (void)state;
    Measure m = {.warmup = 2};
    double work;
    measure_frame_start(&m, 1.0, 2, 100, 5, 7, 0, &work);
    measure_frame_end(&m, 2.0);
    measure_frame_start(&m, 2.0, 3, 200, 6, 8, 0, &work);
    measure_frame_end(&m, 3.0);
    measure_frame_start(&m, 3.0, 1, 300, 9, 10, 0, &work); /* the first measured frame */
    assert_true(m.first_frame_start == 3.0);
    assert_int_equal(m.measured_bytes_base, 300);
    assert_int_equal(m.dup_base, 9);
    assert_int_equal(m.seg_base, 10);
    assert_int_equal(m.clients_seen_max, 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(overhead_comes_from_the_gaps),
        cmocka_unit_test(idle_clients_and_stale_results_are_not_gaps),
        cmocka_unit_test(warm_up_frames_set_the_bases),
    };
    return cmocka_run_group_tests_name("measure", tests, NULL, NULL);
}

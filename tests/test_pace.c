/* test_pace.c - the render scale that holds a frame rate (server/pace.c),
 * driven with made-up frame times: it goes coarser as soon as a frame
 * misses the target, finer only with room to spare, does not flicker
 * between two scales on times that wobble about a boundary, measures a
 * finer scale again after a frame slowed once there, does not leap to
 * every pixel on times that disagree, does not alternate between two
 * scales when the frames are pipelined, comes down
 * from the coarsest in a few frames at the first move, takes frames shown
 * together (a pipelined farm's bursts) as one period, does not take a
 * window's wait for a move as a frame's time, and never
 * leaves scale 1 without a target.  Scales in quarter steps (upscale.h:
 * Q(1), 4, is every pixel, Q(2.5) 10). */
#include "helpers.h"

#include "pace.h"
#include "upscale.h"

enum { W = 1024, H = 768 };

/* Render scale x in quarter steps (upscale.h). */
#define Q(x) ((int)((x) * UPSCALE_ONE))

/* A frame at scale s (quarter steps) of a scene that costs `ns` nanoseconds a pixel. */
static double frame_time(int s, double ns)
{
    return ns * 1e-9 * (double)upscale_side(W, (uint32_t)s) * (double)upscale_side(H, (uint32_t)s);
}

static void coarser_at_once_finer_with_room(void **state)
{
    (void)state;
    Pace p;
    pace_init(&p, 15); /* 66.7 ms a frame */
    assert_int_equal(p.scale, Q(8)); /* nothing measured: a fast first picture */
    p.scale = UPSCALE_ONE;
    /* 600 ns a pixel: 472 ms whole, 118 ms at 2, 76 ms at 2.5, 63 ms at 2.75 */
    int k = pace_update(&p, frame_time(Q(1), 600), Q(1), W, H);
    assert_int_equal(k, Q(2.75));
    for (int i = 0; i < 5; i++)
        k = pace_update(&p, frame_time(k, 600), k, W, H);
    assert_int_equal(k, Q(2.75)); /* steady: 2.5 would miss the target */
    /* the view turns to a cheap part: 100 ns a pixel, 79 ms whole, 35 ms at 1.5 */
    for (int i = 0; i < 5; i++)
        k = pace_update(&p, frame_time(k, 100), k, W, H);
    assert_int_equal(k, Q(1.5));
    /* and to a costly one: 2000 ns a pixel needs scale 5 (63 ms; 4.5: 78 ms) */
    k = pace_update(&p, frame_time(k, 2000), k, W, H);
    assert_true(k >= Q(4));
    for (int i = 0; i < 5; i++)
        k = pace_update(&p, frame_time(k, 2000), k, W, H);
    assert_int_equal(k, Q(5));
}

/* 40 frames whose cost a pixel wobbles between lo and hi ns, from scale *k:
 * how often the scale changed (*k: where it ended). */
static int wobble(Pace *p, int *k, double lo, double hi)
{
    int changes = 0;
    for (int i = 0; i < 40; i++) {
        int next = pace_update(p, frame_time(*k, i % 2 ? lo : hi), *k, W, H);
        changes += next != *k;
        *k = next;
    }
    return changes;
}

static void no_flicker_about_a_boundary(void **state)
{
    (void)state;
    Pace p;
    pace_init(&p, 15);
    p.scale = UPSCALE_ONE;
    /* whole frames at 70-77 ns (55-61 ms: fits, about 0.88 of the target):
     * scale 1.5 would fit easily, 1 fits; a 10% wobble must not move it */
    int k = UPSCALE_ONE;
    assert_int_equal(wobble(&p, &k, 70, 77), 0);
    assert_int_equal(k, UPSCALE_ONE);
    /* at scale 1.5 with whole frames predicted at 0.85 of the target (above
     * PACE_FINER): it stays at 1.5 rather than trying 1 and coming back,
     * until whole frames are measured again (PACE_RETRY frames at 1.5 with
     * room to spare): they fit, and it stays there */
    pace_init(&p, 15);
    p.scale = UPSCALE_ONE;
    k = pace_update(&p, frame_time(Q(1), 120), Q(1), W, H); /* 94 ms whole: coarser */
    assert_int_equal(k, Q(1.5));
    assert_true(PACE_RETRY >= 20);
    for (int i = 0; i < PACE_RETRY - 1; i++)
        k = pace_update(&p, frame_time(k, i % 2 ? 70 : 74), k, W, H);
    assert_int_equal(k, Q(1.5));
    assert_int_equal(wobble(&p, &k, 70, 74), 1);
    assert_int_equal(k, UPSCALE_ONE);
}

/* A frame slowed once at a finer scale (the machine busy) does not hold
 * the pace at a coarser one for good: 479 ns a pixel, 50 ms at 2.75 (0.75
 * of the target), held there; one frame there took 150 ms and sent it
 * coarser, where its frames have room to spare (42 ms at 3) but 2.75's
 * time, carried along, says it would miss; within PACE_RETRY frames it is
 * back at 2.75. */
static void a_slow_frame_is_forgotten(void **state)
{
    (void)state;
    Pace p;
    pace_init(&p, 15);
    int k = p.scale = Q(2.75);
    for (int i = 0; i < 5; i++)
        k = pace_update(&p, frame_time(k, 479), k, W, H);
    assert_int_equal(k, Q(2.75));
    k = pace_update(&p, 0.150, k, W, H);
    assert_true(k > Q(2.75));
    int frames = 0;
    for (; frames < PACE_RETRY + 5 && k != Q(2.75); frames++)
        k = pace_update(&p, frame_time(k, 479), k, W, H);
    assert_int_equal(k, Q(2.75));
    assert_true(frames > 5 && frames <= PACE_RETRY + 2);
}

/* The first move: nothing measured but the coarsest scale's frames, whose
 * time is mostly fixed costs (5 ms a frame here, 300 ns a pixel; target
 * 10 fps: 1.5 would take 110 ms, 2 64 ms, the steady scale): the pace
 * comes down in two frames, 8 -> 2.75 -> 2, never past the target on the
 * way (one scale a frame took seven), and stays. */
static void first_move_comes_down_at_once(void **state)
{
    (void)state;
    Pace p;
    pace_init(&p, 10);
    int k = p.scale, frames = 0, over = 0;
    for (; frames < 10 && k != Q(2); frames++) {
        const double t = 0.005 + frame_time(k, 300);
        over += t > 0.1;
        k = pace_update(&p, t, k, W, H);
    }
    assert_int_equal(k, Q(2));
    assert_true(frames <= 2);
    assert_int_equal(over, 0);
    for (int i = 0; i < 10; i++)
        k = pace_update(&p, 0.005 + frame_time(k, 300), k, W, H);
    assert_int_equal(k, Q(2));
    /* shown through pace_shown, the first frame's own time (from its
     * start) counts: no period before it, yet the scale comes down at
     * once.  The old pace only began a period there, and a pipelined farm
     * rendered four more frames at the coarsest (make demo without a
     * display wrote its 9 moving frames at scales 8 to 3.25). */
    pace_init(&p, 15);
    const double first = 0.005 + frame_time(p.scale, 300);
    k = pace_shown(&p, 10 + first, 10, p.scale, W, H);
    assert_true(k < pace_scales[pace_scale_count - 1]);
    assert_true(frame_time(k, 300) <= PACE_FINER / 15); /* and no further than it fits */
    /* a first frame that took the scene's upload with it (0.5 s: a
     * 1M-triangle model sent to the clients) moves nothing and is not
     * kept: the frames after it bring the scale down as they would alone
     * (kept, its time wore off over a dozen frames at the coarsest) */
    pace_init(&p, 15);
    double now = 10.5;
    k = pace_shown(&p, now, 10.0, p.scale, W, H);
    assert_int_equal(k, pace_scales[pace_scale_count - 1]);
    frames = 0;
    for (; frames < 12 && k == pace_scales[pace_scale_count - 1]; frames++) {
        now += 0.002 + frame_time(k, 300);
        k = pace_shown(&p, now, now - 0.012, k, W, H);
    }
    assert_true(frames <= 6);
}

/* The times of make demo's first frames, pipelined (a frame's time from
 * the one before's end): scale 3.5 measured at 43.7 ms, then 4 at 50.4.
 * Where more pixels measured faster the line through them is flat and
 * predicts every finer scale at 44 ms; the pace went to scale 1 (a frame
 * of 410 ms).  It goes no finer than PACE_REACH times the target allows
 * in proportion to the pixels: scale 2 (4 x 50 ms). */
static void disagreeing_times_do_not_jump(void **state)
{
    (void)state;
    Pace p;
    pace_init(&p, 15);
    const struct {
        int scale;
        double ms;
    } shown[] = {{Q(8), 17.6}, {Q(8), 21.2}, {Q(5), 21.4}, {Q(5), 40.2}, {Q(3.5), 43.7}, {Q(4), 50.4}};
    int k = p.scale;
    for (size_t i = 0; i < sizeof shown / sizeof shown[0]; i++)
        k = pace_update(&p, shown[i].ms * 1e-3, shown[i].scale, W, H);
    assert_true(k >= Q(2));
}

/* A pipelined farm hands over frames in bursts: two shown in one wake-up
 * of the server, the second's period a few microseconds.  At the coarsest
 * scale with 1 ms asked (path.sh's flight of 96 x 72), such a period taken
 * alone is a probe to every pixel at once, and a flight's last moving frame
 * whole made its first still frame the still quality (path.sh failed once
 * in some twenty runs).  Shown through pace_shown, frames that come
 * together count as one period: 9 ms for two frames, 4.5 ms each, over the
 * target, so the pace stays at the coarsest, the first two frames shown
 * together included (where no time was measured yet to average with). */
static void bursts_count_together(void **state)
{
    (void)state;
    Pace p;
    pace_init(&p, 1000);
    const int coarsest = pace_scales[pace_scale_count - 1];
    double now = 100.0;
    int k = pace_shown(&p, now, 0, p.scale, 96, 72);
    for (int i = 0; i < 8; i++) {
        now += i % 2 ? 9e-3 : 1e-5; /* two frames in one wake-up (the first two too), 9 ms on */
        k = pace_shown(&p, now, now - 0.03, k, 96, 72);
        assert_int_equal(k, coarsest);
    }
    /* the same periods one by one: the burst's second is a probe to every pixel */
    pace_init(&p, 1000);
    assert_int_equal(pace_update(&p, 1e-5, coarsest, 96, 72), UPSCALE_ONE);
    /* a still frame starts a period: the next moving frame's is from it */
    pace_init(&p, 15);
    k = pace_shown(&p, 200.0, 199.96, p.scale, W, H);
    k = pace_shown(&p, 200.040, 199.99, k, W, H); /* 40 ms at the coarsest: finer */
    assert_true(k < coarsest);
    const int at = k;
    pace_still(&p, 201.0);
    k = pace_shown(&p, 201.045, 200.99, k, W, H);
    assert_true(k <= at); /* 45 ms from the still frame, not 1 s from the moving one before */
}

/* A window's converged picture waits for a move: the first moving frame's
 * period starts where that frame was started, not at the still frame
 * shown seconds before.  Taken from the still frame, a 3 s wait sent the
 * scale to the coarsest and every finer scale's time up with it: the
 * window showed frames at 4.5 at 58 fps where 15 were asked, coming finer
 * one scale every PACE_RETRY frames (make demo in a window, a key held
 * after the picture converged). */
static void a_wait_is_not_a_frame(void **state)
{
    (void)state;
    Pace p;
    pace_init(&p, 15);
    const double ns = 350; /* the demo's moving frames: 2.25 about 55 ms */
    double now = 10;
    int k = pace_shown(&p, now, now - 0.05, p.scale, W, H);
    for (int i = 0; i < 60; i++) {
        now += frame_time(k, ns);
        k = pace_shown(&p, now, now - 0.05, k, W, H);
    }
    const int settled = k;
    assert_true(settled <= Q(2.75));
    pace_still(&p, now += 0.6); /* the still frames, the last converged */
    now += 3;                   /* a wait, then a key: a moving frame started */
    const double started = now;
    now += frame_time(k, ns);
    k = pace_shown(&p, now, started, k, W, H);
    for (int i = 0; i < 10; i++) {
        assert_true(k <= settled + 1); /* the old pace: the coarsest at once, 4.5 ten frames on */
        now += frame_time(k, ns);
        k = pace_shown(&p, now, now - 0.05, k, W, H);
    }
    assert_int_equal(k, settled);
}

/* A pipelined farm starts the next frame before this one is shown, so a
 * frame's time sets the scale of the frame after next, and the frame
 * between comes back at the scale before.  The demo's flight (make demo in
 * a window) alternated 4 and 4.5, 3.5 and 4.5 a frame each for a second:
 * each frame decided from its own scale, two chains of decisions a frame
 * apart, each stable on its own.  Here the frames at 4 take 57-61 ms
 * (1150-1250 ns a pixel; 4.5 45-49 ms) and one of them 88 ms: the pace
 * goes to 4.5 and, PACE_RETRY frames on, back to 4, where the old one
 * alternated from that frame to the end. */
static void pipelined_frames_do_not_alternate(void **state)
{
    (void)state;
    Pace p;
    pace_init(&p, 15);
    int flight[2] = {p.scale, p.scale}; /* the frame shown next, and the one after it */
    int before[2] = {0, 0}, returns = 0;
    for (int i = 0; i < 120; i++) {
        const int s = flight[0];
        const double ns = i == 40 ? 1800 : 1150 + 25 * ((i * 7) % 5);
        const int next = pace_update(&p, frame_time(s, ns), s, W, H);
        flight[0] = flight[1];
        flight[1] = next;
        returns += i >= 20 && s != before[1] && s == before[0];
        before[0] = before[1];
        before[1] = s;
    }
    assert_true(returns <= 3);
}

static void no_target_keeps_every_pixel(void **state)
{
    (void)state;
    Pace p;
    pace_init(&p, 0);
    assert_int_equal(pace_update(&p, 10.0, UPSCALE_ONE, W, H), UPSCALE_ONE);
    pace_init(&p, 1000); /* out of reach: the coarsest */
    p.scale = UPSCALE_ONE;
    assert_int_equal(pace_update(&p, frame_time(Q(1), 100), Q(1), W, H), pace_scales[pace_scale_count - 1]);
    assert_int_equal(pace_scales[pace_scale_count - 1], UPSCALE_MAX);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(coarser_at_once_finer_with_room),
        cmocka_unit_test(no_flicker_about_a_boundary),
        cmocka_unit_test(first_move_comes_down_at_once),
        cmocka_unit_test(a_slow_frame_is_forgotten),
        cmocka_unit_test(disagreeing_times_do_not_jump),
        cmocka_unit_test(bursts_count_together),
        cmocka_unit_test(a_wait_is_not_a_frame),
        cmocka_unit_test(pipelined_frames_do_not_alternate),
        cmocka_unit_test(no_target_keeps_every_pixel),
    };
    return cmocka_run_group_tests_name("pace", tests, NULL, NULL);
}

/* test_sched.c - the segment scheduler, driven directly as the server and simulator do. */
#include "helpers.h"

#include "scheduler.h"

static Sched *make(uint32_t w, uint32_t h, uint32_t lines, SchedTailRule tail, uint32_t clients)
{
    SchedConfig cfg = {w, h, lines, tail, 8};
    Sched *s = sched_create(&cfg);
    assert_non_null(s);
    sched_set_clients(s, clients);
    sched_begin_frame(s, 1);
    return s;
}

/* New segments tile the frame exactly, in order, whatever the rule. */
static void segments_tile_the_frame(void **state)
{
    (void)state;
    SchedTailRule rules[3] = {sched_tail_static, sched_tail_smart, sched_tail_adaptive};
    for (int r = 0; r < 3; r++) {
        Sched *s = make(37, 23, 4, rules[r], 5);
        uint32_t next = 0;
        Segment seg;
        int client = 0;
        while (next < 37 * 23) {
            assert_true(sched_assign(s, client, &seg));
            assert_int_equal(seg.first, next);
            assert_true(seg.count >= 1 && seg.count <= 4 * 37);
            next += seg.count;
            assert_int_equal(sched_complete(s, client, 1, seg), SCHED_ACCEPT);
            client = (client + 1) % 5;
        }
        assert_int_equal(next, 37 * 23);
        assert_true(sched_frame_done(s));
        assert_false(sched_assign(s, 0, &seg)); /* nothing left at all */
        sched_destroy(s);
    }
}

static void tail_rules_shrink_the_end(void **state)
{
    (void)state;
    const uint32_t seg = 10 * 100;
    /* static: always full size */
    assert_int_equal(sched_tail_static(50000, seg, 8, 1), seg);
    assert_int_equal(sched_tail_static(300, seg, 8, 1), 300);
    /* smart with 8 clients: full size while more than 4 segments are left, then halves */
    assert_int_equal(sched_tail_smart(5 * seg, seg, 8, 1), seg);
    assert_int_equal(sched_tail_smart(4 * seg, seg, 8, 1), seg / 2);
    assert_int_equal(sched_tail_smart(seg / 4, seg, 8, 1), seg / 4);
    /* adaptive: a share of what is left, never below min_pixels, down to parts of a line */
    assert_int_equal(sched_tail_adaptive(100 * seg, seg, 4, 1), seg);
    assert_int_equal(sched_tail_adaptive(4000, seg, 4, 1), 500);
    assert_int_equal(sched_tail_adaptive(800, seg, 4, 64), 100);
    assert_int_equal(sched_tail_adaptive(300, seg, 4, 64), 64);
    assert_int_equal(sched_tail_adaptive(30, seg, 4, 64), 30);
    /* the frame's last segments really are smaller under smart splitting */
    Sched *s = make(100, 100, 10, sched_tail_smart, 8);
    Segment sg;
    uint32_t last = 0, firstsize = 0;
    while (sched_assign(s, 0, &sg)) {
        if (!firstsize)
            firstsize = sg.count;
        last = sg.count;
        sched_complete(s, 0, 1, sg);
    }
    assert_int_equal(firstsize, 1000);
    assert_int_equal(last, 500);
    sched_destroy(s);
    assert_ptr_equal(sched_tail_by_name("adaptive"), sched_tail_adaptive);
    assert_null(sched_tail_by_name("fastest"));
}

static void outstanding_segments_are_reissued_and_first_wins(void **state)
{
    (void)state;
    Sched *s = make(10, 4, 1, sched_tail_static, 2);
    Segment a[4];
    /* client 0 takes two, client 1 takes two: the frame is all handed out */
    assert_true(sched_assign(s, 0, &a[0]));
    assert_true(sched_assign(s, 0, &a[1]));
    assert_true(sched_assign(s, 1, &a[2]));
    assert_true(sched_assign(s, 1, &a[3]));
    assert_int_equal(sched_held(s, 0), 2);
    /* client 1 finishes; client 0 stalls: client 1 gets client 0's segments again */
    assert_int_equal(sched_complete(s, 1, 1, a[2]), SCHED_ACCEPT);
    assert_int_equal(sched_complete(s, 1, 1, a[3]), SCHED_ACCEPT);
    Segment r;
    assert_true(sched_assign(s, 1, &r));
    assert_true(r.first == a[0].first || r.first == a[1].first);
    Segment r2;
    assert_true(sched_assign(s, 1, &r2));
    assert_true(r2.first != r.first);
    assert_int_equal(sched_complete(s, 1, 1, r), SCHED_ACCEPT);
    /* the stalled client wakes up: its copy of that segment is a duplicate */
    assert_int_equal(sched_complete(s, 0, 1, r), SCHED_DUPLICATE);
    assert_int_equal(sched_stats(s).duplicate_pixels, 10);
    assert_false(sched_frame_done(s));
    /* a segment nobody gave this client, and a result for another frame */
    Segment forged = {3, 5};
    assert_int_equal(sched_complete(s, 1, 1, forged), SCHED_UNKNOWN);
    assert_int_equal(sched_complete(s, 1, 0, r), SCHED_STALE);
    sched_destroy(s);
}

static void queued_segments_are_reissued_first(void **state)
{
    (void)state;
    Sched *s = make(10, 6, 1, sched_tail_static, 2);
    Segment a[6];
    /* clients 0, 1, 2 take two each: each renders its first, the second waits */
    for (int i = 0; i < 6; i++)
        assert_true(sched_assign(s, i / 2, &a[i]));
    /* client 2 finishes both; clients 0 and 1 are still on their first */
    assert_int_equal(sched_complete(s, 2, 1, a[4]), SCHED_ACCEPT);
    assert_int_equal(sched_complete(s, 2, 1, a[5]), SCHED_ACCEPT);
    /* it is given a segment that waits behind another, not one in progress
     * (it would come back last); the newest of those first */
    Segment r;
    assert_true(sched_assign(s, 2, &r));
    assert_int_equal(r.first, a[3].first);
    assert_true(sched_assign(s, 2, &r));
    assert_int_equal(r.first, a[1].first);
    /* then the ones in progress, newest first */
    assert_true(sched_assign(s, 2, &r));
    assert_int_equal(r.first, a[2].first);
    /* client 0 finishes its first: its second is no longer queued */
    assert_int_equal(sched_complete(s, 0, 1, a[0]), SCHED_ACCEPT);
    sched_destroy(s);
}

static void released_clients_hold_nothing(void **state)
{
    (void)state;
    Sched *s = make(8, 8, 2, sched_tail_static, 3);
    Segment a, b, c;
    assert_true(sched_assign(s, 7, &a));
    assert_true(sched_assign(s, 7, &b));
    sched_release(s, 7);
    assert_int_equal(sched_held(s, 7), 0);
    assert_int_equal(sched_complete(s, 7, 1, a), SCHED_UNKNOWN); /* it may not deliver any more */
    /* its segments go to the next client once new work runs out */
    while (sched_assign(s, 8, &c))
        assert_int_equal(sched_complete(s, 8, 1, c), SCHED_ACCEPT);
    assert_true(sched_frame_done(s));
    /* a new frame starts clean; the old frame's results are stale */
    sched_begin_frame(s, 2);
    assert_false(sched_frame_done(s));
    assert_int_equal(sched_complete(s, 8, 1, c), SCHED_STALE);
    assert_true(sched_assign(s, 8, &c));
    assert_int_equal(c.first, 0);
    sched_destroy(s);
}

/* The automatic segment size against hand-worked answers: tau =
 * sqrt(o W / N) of render time, in lines, rounded down to a power of two
 * within a factor sqrt(2), at most half a frame per client. */
static void auto_lines_follow_the_rule(void **state)
{
    (void)state;
    assert_int_equal(sched_auto_lines(0, 300, 768, 2), 24);  /* nothing measured: 768 / (16 * 2) */
    assert_int_equal(sched_auto_lines(0, 300, 10, 4), 1);    /* at least a line */
    assert_int_equal(sched_auto_lines(1e6, 100, 1000, 1), 8); /* tau 10000 us = 10 lines of 1000 us: 8 <= 14.1 */
    assert_int_equal(sched_auto_lines(1e6, 100, 1000, 4), 4); /* tau 5000 us = 5 lines: 4 <= 7.07 < 8 */
    assert_int_equal(sched_auto_lines(1e6, 1e8, 1000, 1), 256); /* 10000 lines wanted, half a frame is 500 */
    assert_int_equal(sched_auto_lines(1e6, 1e8, 1000, 0), 256); /* no clients counts as one */
    assert_int_equal(sched_auto_lines(1e6, 1e-6, 1000, 1), 1);  /* almost free segments: one line */
}

/* The dispatch policy: a frame starts (auto-sized or not), each client is
 * topped up to SCHED_IN_FLIGHT segments, a result frees one place, and the
 * segments of a client that left go to the one that is topped up. */
static void top_up_keeps_segments_in_flight(void **state)
{
    (void)state;
    SchedConfig cfg = {10, 10, 4, sched_tail_static, 1};
    Sched *s = sched_create(&cfg);
    assert_non_null(s);
    sched_start_frame(s, 1, 2, 1, 0, 0); /* nothing measured: a sixteenth of the frame a client, at least a line */
    assert_int_equal(sched_config(s)->segment_lines, 1);
    Segment a[SCHED_IN_FLIGHT], b[SCHED_IN_FLIGHT];
    assert_int_equal(sched_top_up(s, 0, a), SCHED_IN_FLIGHT);
    assert_int_equal(sched_top_up(s, 0, b), 0); /* full already */
    assert_int_equal(a[0].first, 0);
    assert_int_equal(a[1].first, 10); /* in the order it renders them */
    assert_int_equal(sched_top_up(s, 1, b), SCHED_IN_FLIGHT);
    assert_int_equal(b[0].first, 20);
    assert_int_equal(sched_complete(s, 0, 1, a[0]), SCHED_ACCEPT);
    Segment queue[64];
    uint32_t head = 0, tail = 0;
    queue[tail++] = a[1];
    tail += sched_top_up(s, 0, &queue[tail]);
    assert_int_equal(tail, 2);
    assert_int_equal(queue[1].first, 40);
    /* client 1 leaves holding 20 and 30; client 0 runs the frame out,
     * rendering in order and topped up after each result */
    sched_release(s, 1);
    int got20 = 0, got30 = 0;
    while (head < tail && !sched_frame_done(s)) {
        Segment g = queue[head++];
        assert_int_equal(sched_complete(s, 0, 1, g), SCHED_ACCEPT);
        got20 |= g.first == 20;
        got30 |= g.first == 30;
        assert_true(tail + SCHED_IN_FLIGHT <= 64);
        tail += sched_top_up(s, 0, &queue[tail]);
        assert_true(sched_held(s, 0) <= SCHED_IN_FLIGHT);
    }
    assert_true(sched_frame_done(s));
    assert_true(got20 && got30);
    /* the next frame, sized by hand: the size stays */
    sched_set_segment_lines(s, 3);
    sched_start_frame(s, 2, 1, 0, 5e6, 100);
    assert_int_equal(sched_config(s)->segment_lines, 3);
    assert_int_equal(sched_top_up(s, 0, a), SCHED_IN_FLIGHT);
    assert_int_equal(a[1].first, 30);
    sched_destroy(s);
}

/* Pipelined frames: two frames in flight.  The older frame's fresh work
 * goes first, then the newer's; segments again only when neither has any
 * fresh work, the older's first; a client that cannot render the older
 * frame gets the newer only; orphans of a client that left count as fresh. */
static void pair_top_up_serves_the_older_frame_first(void **state)
{
    (void)state;
    Sched *older = make(10, 4, 1, sched_tail_static, 2), *newer = make(10, 4, 1, sched_tail_static, 2);
    sched_begin_frame(newer, 2);
    Segment g[SCHED_IN_FLIGHT];
    Sched *from[SCHED_IN_FLIGHT];
    /* the older frame handed out: client 0 holds lines 0 and 1, client 1 lines 2 and 3 */
    assert_int_equal(sched_top_up_pair(older, NULL, 0, g, from), 2);
    assert_true(from[0] == older && from[1] == older && g[0].first == 0 && g[1].first == 10);
    assert_int_equal(sched_top_up_pair(older, NULL, 1, g, from), 2);
    assert_false(sched_has_fresh(older)); /* the moment to start the newer frame */
    assert_true(sched_has_fresh(newer));
    /* full: nothing more, over both frames */
    assert_int_equal(sched_top_up_pair(older, newer, 0, g, from), 0);
    /* line 0 done: the newer frame's first line, not line 2 again */
    assert_int_equal(sched_complete(older, 0, 1, (Segment){0, 10}), SCHED_ACCEPT);
    assert_int_equal(sched_top_up_pair(older, newer, 0, g, from), 1);
    assert_true(from[0] == newer && g[0].first == 0);
    /* client 1 leaves: its lines 2 and 3 are fresh again and go before the newer frame's */
    sched_release(older, 1);
    assert_true(sched_has_fresh(older));
    assert_int_equal(sched_complete(older, 0, 1, (Segment){10, 10}), SCHED_ACCEPT);
    assert_int_equal(sched_top_up_pair(older, newer, 0, g, from), 1);
    assert_true(from[0] == older && g[0].first == 30); /* the newest orphan first, as sched_assign */
    /* a client that joined after the newer frame began gets only the newer's */
    assert_int_equal(sched_top_up_pair(NULL, newer, 2, g, from), 2);
    assert_true(from[0] == newer && from[1] == newer && g[0].first == 10 && g[1].first == 20);
    /* client 3 may take either: the last fresh lines (older 2, newer 3), then
     * segments again, the older frame's first */
    assert_int_equal(sched_top_up_pair(older, newer, 3, g, from), 2);
    assert_true(from[0] == older && g[0].first == 20 && from[1] == newer && g[1].first == 30);
    assert_false(sched_has_fresh(older) || sched_has_fresh(newer));
    assert_int_equal(sched_complete(older, 3, 1, g[0]), SCHED_ACCEPT);
    assert_int_equal(sched_top_up_pair(older, newer, 3, g, from), 1);
    assert_true(from[0] == older && g[0].first == 30); /* held by client 0: the older frame's tail again */
    sched_destroy(older);
    sched_destroy(newer);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(segments_tile_the_frame),
        cmocka_unit_test(tail_rules_shrink_the_end),
        cmocka_unit_test(outstanding_segments_are_reissued_and_first_wins),
        cmocka_unit_test(queued_segments_are_reissued_first),
        cmocka_unit_test(released_clients_hold_nothing),
        cmocka_unit_test(auto_lines_follow_the_rule),
        cmocka_unit_test(top_up_keeps_segments_in_flight),
        cmocka_unit_test(pair_top_up_serves_the_older_frame_first),
    };
    return cmocka_run_group_tests_name("sched", tests, NULL, NULL);
}

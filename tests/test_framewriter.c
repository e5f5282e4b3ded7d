/* test_framewriter.c - frames written on the writer's thread
 * (server/framewriter.c): more frames than slots, given as fast as they
 * come, each file the frame it was given (a slot is not filled again
 * before its frame is written); a frame that cannot be written is counted
 * and named; frames still queued when the writer is destroyed are written. */
#include "helpers.h"

#include <stdlib.h>

#include "framewriter.h"

enum { W = 37, H = 23 };

static void frame_fill(uint8_t *px, int n)
{
    for (int i = 0; i < W * H * 3; i++)
        px[i] = (uint8_t)(i * 7 + n * 31);
}

static void frame_check(const char *path, int n)
{
    int w, h;
    uint8_t *got, want[W * H * 3];
    Err err;
    assert_int_equal(image_read_png(path, &w, &h, &got, &err), 0);
    assert_int_equal(w, W);
    assert_int_equal(h, H);
    frame_fill(want, n);
    assert_memory_equal(got, want, sizeof want);
    free(got);
}

static void frames_written_in_order(void **state)
{
    (void)state;
    Err err;
    FrameWriter *fw = framewriter_create(W, H, 3, 2, &err);
    assert_non_null(fw);
    uint8_t px[W * H * 3];
    char path[512];
    for (int n = 0; n < 12; n++) {
        frame_fill(px, n);
        snprintf(path, sizeof path, "%s/order-%02d.png", test_tmpdir(), n);
        assert_int_equal(framewriter_put(fw, path, px, IMAGE_SRGB, &err), 0);
        memset(px, 0, sizeof px); /* the caller's buffer is its own again */
    }
    assert_int_equal(framewriter_flush(fw, &err), 0);
    for (int n = 0; n < 12; n++) {
        snprintf(path, sizeof path, "%s/order-%02d.png", test_tmpdir(), n);
        frame_check(path, n);
    }
    framewriter_destroy(fw);
}

static void failures_counted_and_named(void **state)
{
    (void)state;
    Err err;
    FrameWriter *fw = framewriter_create(W, H, 3, 2, &err);
    assert_non_null(fw);
    uint8_t px[W * H * 3];
    frame_fill(px, 1);
    char bad[512], good[512];
    snprintf(bad, sizeof bad, "%s/no-such-dir/frame.png", test_tmpdir());
    snprintf(good, sizeof good, "%s/after-bad.png", test_tmpdir());
    int failed = framewriter_put(fw, bad, px, IMAGE_SRGB, &err);
    failed += framewriter_put(fw, bad, px, IMAGE_SRGB, &err);
    failed += framewriter_put(fw, good, px, IMAGE_SRGB, &err);
    failed += framewriter_flush(fw, &err);
    assert_int_equal(failed, 2);
    assert_non_null(strstr(err.msg, "no-such-dir"));
    frame_check(good, 1); /* the writer goes on after a failure */
    assert_int_equal(framewriter_flush(fw, &err), 0); /* each failure said once */
    framewriter_destroy(fw);
}

static void destroy_writes_what_is_queued(void **state)
{
    (void)state;
    Err err;
    FrameWriter *fw = framewriter_create(W, H, 3, 3, &err);
    assert_non_null(fw);
    uint8_t px[W * H * 3];
    char path[512];
    for (int n = 0; n < 3; n++) {
        frame_fill(px, 40 + n);
        snprintf(path, sizeof path, "%s/last-%d.png", test_tmpdir(), n);
        assert_int_equal(framewriter_put(fw, path, px, IMAGE_SRGB, &err), 0);
    }
    framewriter_destroy(fw);
    for (int n = 0; n < 3; n++) {
        snprintf(path, sizeof path, "%s/last-%d.png", test_tmpdir(), n);
        frame_check(path, 40 + n);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(frames_written_in_order),
        cmocka_unit_test(failures_counted_and_named),
        cmocka_unit_test(destroy_writes_what_is_queued),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

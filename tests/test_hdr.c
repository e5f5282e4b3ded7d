/* test_hdr.c - the Radiance .hdr reader (image/hdr_read.h): lanray's own
 * files and run-length coded ones read back pixel for pixel, and bad
 * bytes refused with what was wrong and where, without reading past them. */
#include "helpers.h"

#include <stdlib.h>
#include <string.h>

#include "image/hdr_read.h"

static int parse(const char *text, size_t n, int *w, int *h, uint8_t **px, Err *err)
{
    return hdr_parse((const uint8_t *)text, n, "t.hdr", w, h, px, err);
}

static void flat_and_coded_scanlines_read_back(void **state)
{
    (void)state;
    /* 8 pixels a row, 2 rows: the first flat, the second coded (a run of
     * 8 of each channel but the last, which is literal) */
    uint8_t buf[256];
    size_t n = 0;
    const char *head = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+Y 2 +X 8\n";
    memcpy(buf, head, strlen(head));
    n = strlen(head);
    for (int x = 0; x < 8; x++) { /* flat: the file's first row is the bottom one (+Y) */
        const uint8_t p[4] = {(uint8_t)x, 2, 3, 130};
        memcpy(buf + n, p, 4);
        n += 4;
    }
    const uint8_t coded[] = {2, 2, 0, 8, 128 + 8, 9, 128 + 8, 10, 128 + 8, 11, 8, 1, 2, 3, 4, 5, 6, 7, 8};
    memcpy(buf + n, coded, sizeof coded);
    n += sizeof coded;
    int w, h;
    uint8_t *px;
    Err err;
    if (hdr_parse(buf, n, "t.hdr", &w, &h, &px, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(w, 8);
    assert_int_equal(h, 2);
    for (int x = 0; x < 8; x++) {
        /* top row first: the coded row (the file's second) is on top */
        assert_int_equal(px[4 * x], 9);
        assert_int_equal(px[4 * x + 1], 10);
        assert_int_equal(px[4 * x + 2], 11);
        assert_int_equal(px[4 * x + 3], x + 1);
        assert_int_equal(px[32 + 4 * x], x);
        assert_int_equal(px[32 + 4 * x + 3], 130);
    }
    free(px);
}

static void expect_refused(const uint8_t *data, size_t n, const char *why)
{
    int w, h;
    uint8_t *px = NULL;
    Err err;
    assert_int_equal(hdr_parse(data, n, "t.hdr", &w, &h, &px, &err), -1);
    assert_null(px);
    if (!strstr(err.msg, why) || !strstr(err.msg, "t.hdr"))
        fail_msg("'%s' does not name the file and say '%s'", err.msg, why);
}

static void bad_bytes_are_refused(void **state)
{
    (void)state;
    const char *not_hdr = "P6\n1 1\n255\nabc";
    expect_refused((const uint8_t *)not_hdr, strlen(not_hdr), "not a Radiance .hdr");
    const char *format = "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\nabcd";
    expect_refused((const uint8_t *)format, strlen(format), "FORMAT=32-bit_rle_rgbe");
    const char *no_size = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n";
    expect_refused((const uint8_t *)no_size, strlen(no_size), "without a resolution line");
    const char *bad_size = "#?RADIANCE\n\n-Y 0 +X 4\n";
    expect_refused((const uint8_t *)bad_size, strlen(bad_size), "line 3");
    const char *too_big = "#?RADIANCE\n\n-Y 70000 +X 4\n";
    expect_refused((const uint8_t *)too_big, strlen(too_big), "line 3");
    /* a huge image in a few bytes: refused before allocating */
    const char *huge = "#?RADIANCE\n\n-Y 65536 +X 65536\nabcd";
    expect_refused((const uint8_t *)huge, strlen(huge), "cannot fit");
    /* cut short: the second of two flat rows missing */
    const char *cut = "#?RADIANCE\n\n-Y 2 +X 1\nabcd";
    expect_refused((const uint8_t *)cut, strlen(cut) + 0, "scanline 2 of 2");
    /* a run that would write past the row's end, and a run of length 0 */
    uint8_t run[64];
    const char *head = "#?RADIANCE\n\n-Y 1 +X 8\n";
    size_t n = strlen(head);
    memcpy(run, head, n);
    const uint8_t over[] = {2, 2, 0, 8, 128 + 9, 1};
    memcpy(run + n, over, sizeof over);
    expect_refused(run, n + sizeof over, "scanline 1 of 1");
    const uint8_t zero[] = {2, 2, 0, 8, 0, 1};
    memcpy(run + n, zero, sizeof zero);
    expect_refused(run, n + sizeof zero, "scanline 1 of 1");
    /* every prefix of a good file is refused, none read past its end (ASan) */
    const uint8_t good[] = {'#', '?', 'R', 'A', 'D', 'I', 'A', 'N', 'C', 'E', '\n', '\n', '-', 'Y', ' ', '1', ' ', '+',
                            'X', ' ', '8', '\n', 2, 2, 0, 8, 136, 1, 136, 2, 136, 3, 136, 4};
    for (size_t k = 0; k < sizeof good; k++) {
        uint8_t *copy = malloc(k + 1);
        memcpy(copy, good, k);
        int w, h;
        uint8_t *px = NULL;
        assert_int_equal(hdr_parse(copy, k, "t.hdr", &w, &h, &px, NULL), -1);
        free(copy);
    }
    int w, h;
    uint8_t *px;
    assert_int_equal(parse((const char *)good, sizeof good, &w, &h, &px, NULL), 0);
    free(px);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(flat_and_coded_scanlines_read_back),
        cmocka_unit_test(bad_bytes_are_refused),
    };
    return cmocka_run_group_tests_name("hdr", tests, NULL, NULL);
}

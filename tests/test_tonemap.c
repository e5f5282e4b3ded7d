/* test_tonemap.c - the view transforms of render/tonemap.h against their
 * published formulas: ACES as Narkowicz's fit (0 stays 0, white 1 shows
 * 2.54 / 3.16, rising everywhere, towards 2.51 / 2.43), Khronos PBR
 * Neutral (a grey below the compression less its offset, the toe under
 * 0.08, the peak compressed towards 1 with the channels' order kept, no
 * channel past 1), none passing the light as it is; and 8-bit codes made
 * through them (pixel_put_codes): a light of 4 is 255 without and below
 * 255 with either curve. */
#include "helpers.h"

#include <math.h>

#include "render/pixel.h"
#include "render/tonemap.h"

static void aces_is_narkowicz_fit(void **state)
{
    (void)state;
    assert_true(tonemap_aces(R(0)) == R(0));
    assert_true(tonemap_aces(R(-1)) == R(0));
    assert_float_equal(tonemap_aces(R(1)), 2.54 / 3.16, 1e-6);
    assert_float_equal(tonemap_aces(R(0.18)), 0.18 * (2.51 * 0.18 + 0.03) / (0.18 * (2.43 * 0.18 + 0.59) + 0.14), 1e-6);
    real last = R(0);
    for (int i = 1; i <= 100000; i++) {
        const real x = (real)i * R(0.01), y = tonemap_aces(x);
        /* rising; past 10 (white, and past it) the float's last bits may waver */
        assert_true(x <= R(10) ? y > last : y > R(0.99) && y < R(2.51 / 2.43));
        last = y;
    }
    assert_true(last < R(2.51 / 2.43) && last > R(1));
}

static void neutral_keeps_colours_and_rolls_off(void **state)
{
    (void)state;
    vec3 g = tonemap_neutral(v3(R(0.5), R(0.5), R(0.5)));
    assert_float_equal(g.x, 0.46, 1e-6);
    assert_float_equal(g.z, 0.46, 1e-6);
    g = tonemap_neutral(v3(R(0.05), R(0.05), R(0.05))); /* the toe: less x - 6.25 x^2 */
    assert_float_equal(g.y, 0.05 - (0.05 - 6.25 * 0.05 * 0.05), 1e-6);
    real last = R(0);
    for (int i = 1; i <= 20000; i++) {
        const vec3 c = tonemap_neutral(v3((real)i * R(0.01), (real)i * R(0.004), (real)i * R(0.001)));
        assert_true(c.x >= c.y && c.y >= c.z);             /* the hue's order kept */
        assert_true(c.x <= R(1) && c.x >= last - R(1e-6)); /* rising, never past 1 */
        last = c.x;
    }
    assert_true(last > R(0.99));
    const vec3 same = tonemap_apply(v3(R(3), R(0.2), R(-1)), TONEMAP_NONE);
    assert_true(same.x == R(3) && same.y == R(0.2) && same.z == R(-1));
}

static void codes_through_a_curve(void **state)
{
    (void)state;
    uint8_t none[3], aces[3], neutral[3];
    pixel_put_codes(none, v3(R(4), R(4), R(4)), R(1), TONEMAP_NONE, 0);
    pixel_put_codes(aces, v3(R(4), R(4), R(4)), R(1), TONEMAP_ACES, 0);
    pixel_put_codes(neutral, v3(R(4), R(4), R(0.5)), R(1), TONEMAP_NEUTRAL, 0);
    assert_int_equal(none[0], 255);
    assert_true(aces[0] < 255 && aces[0] > 240);
    assert_true(neutral[0] < 255 && neutral[2] < neutral[0]);
    /* the exposure before the curve */
    uint8_t half[3], dimmed[3];
    pixel_put_codes(half, v3(R(2), R(2), R(2)), R(1), TONEMAP_ACES, 0);
    pixel_put_codes(dimmed, v3(R(4), R(4), R(4)), R(0.5), TONEMAP_ACES, 0);
    assert_memory_equal(half, dimmed, 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(aces_is_narkowicz_fit),
        cmocka_unit_test(neutral_keeps_colours_and_rolls_off),
        cmocka_unit_test(codes_through_a_curve),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

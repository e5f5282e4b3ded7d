/* test_trig.c - lanray's own atan2, sine and cosine (base/trig.h) against
 * the C library's in double: within 3e-7 (atan2 relative, on every
 * octant and its edges; sine and cosine within 2e-7, over the turns a
 * panorama's draws take), and the C library's rules at zeros, the axes
 * and NaNs. */
#include "helpers.h"

#include "base/trig.h"

static double unit(uint32_t *x)
{
    *x = *x * 1664525u + 1013904223u;
    return (double)(*x >> 8) / 16777216.0;
}

static void atan2_is_within_3e7(void **state)
{
    (void)state;
    uint32_t x = 99;
    double worst = 0.0;
    for (int i = 0; i < 400000; i++) {
        /* any direction, and near the octants' edges (|y| = |x|, an axis) */
        const double ang = (unit(&x) - 0.5) * 2.0 * 3.141592653589793, len = 0.001 + 1000.0 * unit(&x);
        const double nudge = i % 4 == 0 ? floor(ang / 0.7853981633974483 + 0.5) * 0.7853981633974483 - ang : 0.0;
        const real yy = (real)(len * sin(ang + nudge * (1.0 - 1e-6 * unit(&x)))),
                   xx = (real)(len * cos(ang + nudge * (1.0 - 1e-6 * unit(&x))));
        const double want = atan2((double)yy, (double)xx), got = (double)trig_atan2(yy, xx);
        const double err = fabs(got - want) / (fabs(want) > 1e-30 ? fabs(want) : 1.0);
        if (err > worst)
            worst = err;
        if (!(err <= 3e-7))
            fail_msg("atan2(%.9g, %.9g) = %.9g, the library's %.9g", (double)yy, (double)xx, got, want);
    }
    assert_true(worst > 0.0 || sizeof(real) == sizeof(double)); /* the float build's is its own */
}

static void atan2_keeps_the_library_rules(void **state)
{
    (void)state;
    const real pi = (real)3.14159265358979323846, q = pi / R(2);
    assert_true(trig_atan2(R(0), R(1)) == R(0) && !signbit(trig_atan2(R(0), R(1))));
    assert_true(trig_atan2(-R(0), R(1)) == R(0) && signbit(trig_atan2(-R(0), R(1))));
    assert_true(trig_atan2(R(0), R(-1)) == pi && trig_atan2(-R(0), R(-1)) == -pi);
    assert_true(trig_atan2(R(1), R(0)) == q && trig_atan2(R(-1), R(0)) == -q);
    assert_true(trig_atan2(R(0), R(0)) == R(0));
    assert_true(trig_atan2(R(2), R(2)) == pi / R(4) && trig_atan2(R(-3), R(-3)) == R(-3) * pi / R(4));
    assert_true(isnan(trig_atan2((real)NAN, R(1))) && isnan(trig_atan2(R(1), (real)NAN)));
}

static void sincos_is_within_2e7(void **state)
{
    (void)state;
    uint32_t x = 7;
    for (int i = 0; i < 400000; i++) {
        /* the draws' polar angles (0..pi) and turns (-3 pi .. 3 pi), and the quadrants' edges */
        double a = (unit(&x) - 0.5) * 6.0 * 3.141592653589793;
        if (i % 4 == 0)
            a = floor(a / 1.5707963267948966 + 0.5) * 1.5707963267948966 + (unit(&x) - 0.5) * 1e-5;
        real s, c;
        trig_sincos((real)a, &s, &c);
        const double ar = (double)(real)a;
        if (!(fabs((double)s - sin(ar)) <= 2e-7 && fabs((double)c - cos(ar)) <= 2e-7))
            fail_msg("sincos(%.9g) = (%.9g, %.9g), the library's (%.9g, %.9g)", ar, (double)s, (double)c, sin(ar),
                     cos(ar));
    }
    real s, c;
    trig_sincos(R(0), &s, &c);
    assert_true(s == R(0) && c == R(1));
    trig_sincos((real)NAN, &s, &c);
    assert_true(isnan(s) && isnan(c));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(atan2_is_within_3e7),
        cmocka_unit_test(atan2_keeps_the_library_rules),
        cmocka_unit_test(sincos_is_within_2e7),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

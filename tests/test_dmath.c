/* test_dmath.c - lanray's own sine and cosine, exp2, log2, pow and exp in
 * double (base/dmath.h) against the C library's long double ones: within
 * a few units of a double's last place, the C library's rules at the
 * edges, and the same bits as when these tests were written (a hash of
 * 60000 results: what "the same on every machine" means, which a compiler
 * that contracted or reordered the arithmetic would break). */
#include "helpers.h"

#include "base/dmath.h"

static double unit(uint64_t *x)
{
    *x = *x * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*x >> 11) / 9007199254740992.0;
}

static void sincos_within_4e16(void **state)
{
    (void)state;
    uint64_t x = 3;
    for (int i = 0; i < 300000; i++) {
        /* small angles, turns, the quadrants' edges, and up to 10^6 */
        double a = i % 3 == 0 ? (unit(&x) - 0.5) * 20.0 : i % 3 == 1 ? (unit(&x) - 0.5) * 2e6 : 0.0;
        if (i % 3 == 2)
            a = floor((unit(&x) - 0.5) * 200.0) * 1.5707963267948966 + (unit(&x) - 0.5) * 1e-6;
        double s, c;
        dmath_sincos(a, &s, &c);
        const long double ws = sinl((long double)a), wc = cosl((long double)a);
        if (!(fabsl((long double)s - ws) <= 4e-16L && fabsl((long double)c - wc) <= 4e-16L))
            fail_msg("sincos(%.17g) = (%.17g, %.17g), want (%.17Lg, %.17Lg)", a, s, c, ws, wc);
    }
    double s, c;
    dmath_sincos(0.0, &s, &c);
    assert_true(s == 0.0 && c == 1.0);
    dmath_sincos((double)NAN, &s, &c);
    assert_true(isnan(s) && isnan(c));
    dmath_sincos(HUGE_VAL, &s, &c);
    assert_true(isnan(s) && isnan(c));
    dmath_sincos(1e300, &s, &c); /* far: reduced otherwise, still on the circle */
    assert_true(fabs(s * s + c * c - 1.0) < 1e-15);
}

static void exp2_and_log2_within_a_few_units(void **state)
{
    (void)state;
    uint64_t x = 5;
    for (int i = 0; i < 300000; i++) {
        const double t = (unit(&x) - 0.5) * 2000.0;
        const long double want = exp2l((long double)t);
        const double got = dmath_exp2(t);
        if (want >= 2.2250738585072014e-308L && !(fabsl((long double)got - want) <= 6.7e-16L * want))
            fail_msg("exp2(%.17g) = %.17g, want %.17Lg", t, got, want);
        const double m = 0.5 + 1.5 * unit(&x), far = ldexp(0.5 + unit(&x), (int)(unit(&x) * 2000.0) - 1000);
        if (!(fabsl((long double)dmath_log2(m) - log2l((long double)m)) <= 4e-16L))
            fail_msg("log2(%.17g) = %.17g, want %.17Lg", m, dmath_log2(m), log2l((long double)m));
        const long double wf = log2l((long double)far);
        if (!(fabsl((long double)dmath_log2(far) - wf) <= 2.3e-16L * fabsl(wf) + 4e-16L))
            fail_msg("log2(%.17g) = %.17g, want %.17Lg", far, dmath_log2(far), wf);
    }
    for (int n = -1074; n <= 1023; n++) /* powers of two exactly, subnormals too */
        assert_true(dmath_exp2((double)n) == ldexp(1.0, n));
    assert_true(dmath_exp2(1024.0) == HUGE_VAL && dmath_exp2(-1100.0) == 0.0 && isnan(dmath_exp2((double)NAN)));
    assert_true(dmath_log2(1.0) == 0.0 && dmath_log2(8.0) == 3.0 && dmath_log2(0x1p-1074) == -1074.0);
    assert_true(dmath_log2(0.0) == -HUGE_VAL && isnan(dmath_log2(-1.0)) && dmath_log2(HUGE_VAL) == HUGE_VAL);
}

static void pow_and_exp_within_a_few_units(void **state)
{
    (void)state;
    uint64_t x = 11;
    for (int i = 0; i < 300000; i++) {
        /* a highlight's cosines to its powers, gamma's, an exposure's 2^E, and wide */
        const double b = i % 2 ? unit(&x) : ldexp(0.5 + unit(&x), (int)(unit(&x) * 200.0) - 100);
        const double y = i % 3 == 0 ? floor(unit(&x) * 1000.0) : i % 3 == 1 ? 1.0 / (1.0 + 10.0 * unit(&x))
                                                                              : (unit(&x) - 0.5) * 60.0;
        const long double want = powl((long double)b, (long double)y);
        if (!(want > 2.2250738585072014e-308L && want < 1.7976931348623157e308L))
            continue;
        const double got = dmath_pow(b, y);
        /* log2's error grows with y, and the rounding of their product with it */
        const long double t = fabsl((long double)y * log2l((long double)b)) + fabsl((long double)y);
        if (!(fabsl((long double)got - want) <= 3e-16L * (4.0L + t) * want))
            fail_msg("pow(%.17g, %.17g) = %.17g, want %.17Lg", b, y, got, want);
        const double e = (unit(&x) - 0.5) * 1400.0;
        const long double we = expl((long double)e);
        if (we > 2.2250738585072014e-308L && we < 1.7976931348623157e308L &&
            !(fabsl((long double)dmath_exp(e) - we) <= 6.7e-16L * we))
            fail_msg("exp(%.17g) = %.17g, want %.17Lg", e, dmath_exp(e), we);
    }
    /* the library's rules at the edges */
    assert_true(dmath_pow(0.7, 0.0) == 1.0 && dmath_pow(1.0, (double)NAN) == 1.0 && dmath_pow((double)NAN, 0.0) == 1.0);
    assert_true(dmath_pow(2.0, 10.0) == 1024.0 && dmath_pow(2.0, -3.0) == 0.125 && dmath_pow(0.25, 0.5) == 0.5);
    assert_true(dmath_pow(-2.0, 3.0) == -8.0 && dmath_pow(-2.0, 2.0) == 4.0 && isnan(dmath_pow(-2.0, 0.5)));
    assert_true(dmath_pow(0.0, 2.0) == 0.0 && dmath_pow(0.0, -1.0) == HUGE_VAL && signbit(dmath_pow(-0.0, 3.0)));
    assert_true(dmath_pow(HUGE_VAL, 2.0) == HUGE_VAL && dmath_pow(HUGE_VAL, -2.0) == 0.0);
    assert_true(dmath_pow(0.5, HUGE_VAL) == 0.0 && dmath_pow(2.0, HUGE_VAL) == HUGE_VAL);
    assert_true(isnan(dmath_pow((double)NAN, 2.0)) && isnan(dmath_pow(2.0, (double)NAN)));
    assert_true(dmath_exp(0.0) == 1.0 && dmath_exp(-800.0) == 0.0 && dmath_exp(800.0) == HUGE_VAL);
    /* a float rounded from them: the library's float functions' value wherever those round correctly */
    assert_true((float)dmath_pow(0.5f, 20.0f) == 0x1p-20f && (float)dmath_pow(0.81f, 1.0f) == 0.81f);
}

static uint64_t mix(uint64_t h, double v)
{
    uint64_t b;
    memcpy(&b, &v, sizeof b);
    return (h ^ b) * 0x100000001b3ull;
}

static void the_same_bits_as_written(void **state)
{
    (void)state;
    uint64_t x = 17, h = 1469598103934665603ull;
    for (int i = 0; i < 10000; i++) {
        double s, c;
        dmath_sincos((unit(&x) - 0.5) * 100.0, &s, &c);
        h = mix(mix(h, s), c);
        h = mix(h, dmath_exp2((unit(&x) - 0.5) * 300.0));
        h = mix(h, dmath_log2(unit(&x) * 1e6));
        h = mix(h, dmath_pow(unit(&x), floor(unit(&x) * 200.0)));
        h = mix(h, dmath_exp(-unit(&x) * 50.0));
    }
    /* recorded on 2026-12-01 (AMD EPYC, gcc 12, -O2 -ffp-contract=off); any machine must give it */
    if (h != 0xb58cd291b860f28dull)
        fail_msg("dmath's results hash to %#llx, not the bits recorded", (unsigned long long)h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sincos_within_4e16),
        cmocka_unit_test(exp2_and_log2_within_a_few_units),
        cmocka_unit_test(pow_and_exp_within_a_few_units),
        cmocka_unit_test(the_same_bits_as_written),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

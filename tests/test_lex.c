/* test_lex.c - the number readers of the text formats: lex_double's fast
 * path gives exactly strtod's double (bit for bit) on every form a file may
 * hold, and refuses what strtod refuses; lex_long and lex_strtol10 give
 * strtol's answers. */
#include "helpers.h"

#include <errno.h>
#include <math.h>

#include "base/lex.h"

/* lex_double against strtod on one string: the same verdict, the same bits */
static void agrees(const char *s)
{
    char *end;
    double want = strtod(s, &end), got = 12345;
    int ok = end != s && *end == 0 && isfinite(want);
    int rc = lex_double(s, &got);
    if (rc != (ok ? 0 : -1))
        fail_msg("'%s': lex_double %s, strtod %s", s, rc ? "refuses" : "takes", ok ? "takes" : "refuses");
    if (ok && memcmp(&got, &want, sizeof got) != 0)
        fail_msg("'%s': lex_double %.17g, strtod %.17g", s, got, want);
}

static void numbers_match_strtod(void **state)
{
    (void)state;
    const char *fixed[] = {"0", "-0", "+0", "0.0", "-0.000000", "1", "-1", "1.", ".5", "-.5", "+.5", "1.e5", "1e5",
                           "1E-5", "1e+22", "1e23", "1e-22", "1e-23", "123456789012345", "1234567890123456",
                           "12345678901234567890", "0.1", "0.2", "0.3", "9007199254740993", "1.011951",
                           "0.000000000000000000000000001", "1e308", "1e309", "-1e-400", "4.9e-324", "0x10", "0x1p3",
                           "inf", "-inf", "nan", "infinity", "", "-", "+", ".", "e5", "1e", "1e+", "1e-", "1.2.3",
                           "1,5", "1 ", " 1", "--1", "1e5x", "00000000000000000000001.5", "1.50000000000000000000",
                           "0.0000000000000000000000000000000000000001", "999999999999999", "1e0000000000000000002"};
    for (size_t i = 0; i < sizeof fixed / sizeof *fixed; i++)
        agrees(fixed[i]);
    /* random decimals in the forms exporters write: fixed and scientific,
     * 1 to 20 significant digits, signs, leading and trailing zeros */
    Rng rng = {0x9e3779b97f4a7c15ull};
    char buf[96];
    for (int i = 0; i < 400000; i++) {
        uint64_t r = rng_next(&rng);
        int n = 0, digits = 1 + (int)(r % 20), point = (int)((r >> 8) % 24) - 2, form = (int)((r >> 16) % 4);
        if ((r >> 20) & 1)
            buf[n++] = '-';
        else if (((r >> 21) & 7) == 0)
            buf[n++] = '+';
        if (point <= 0) {
            buf[n++] = '0';
            buf[n++] = '.';
            for (int k = point; k < 0; k++)
                buf[n++] = '0';
        }
        for (int k = 0; k < digits; k++) {
            buf[n++] = (char)('0' + rng_next(&rng) % 10);
            if (k + 1 == point && k + 1 < digits)
                buf[n++] = '.';
        }
        if (form >= 2)
            n += snprintf(buf + n, sizeof buf - (size_t)n, "e%s%d", form == 3 ? "-" : "",
                          (int)(rng_next(&rng) % (form == 3 ? 40 : 30)));
        buf[n] = 0;
        agrees(buf);
    }
}

static void long_matches_strtol(void **state)
{
    (void)state;
    const char *fixed[] = {"0", "-1", "+7", "123", "9223372036854775807", "9223372036854775808",
                           "-9223372036854775808", "-9223372036854775809", "", "-", "1x", " 1", "1.0"};
    for (size_t i = 0; i < sizeof fixed / sizeof *fixed; i++) {
        char *end;
        errno = 0;
        long want = strtol(fixed[i], &end, 10), got = 0;
        int ok = end != fixed[i] && *end == 0 && errno != ERANGE;
        int rc = lex_long(fixed[i], &got);
        if (rc != (ok ? 0 : -1) || (ok && got != want))
            fail_msg("'%s': lex_long %d %ld, strtol %d %ld", fixed[i], rc, got, ok, want);
    }
}

/* lex_strtol10 against strtol: the same value and the same end, on the
 * corner forms of OBJ faces and on what strtol treats specially */
static void strtol10_matches_strtol(void **state)
{
    (void)state;
    const char *fixed[] = {"1", "12/7/12", "-3//-3", "+5", "0", "-0", "007", "", "-", "+", "/2", " 12", "\t-4",
                           "+-1", "123456789012345678/1", "1234567890123456789", "99999999999999999999",
                           "-9223372036854775808", "-9223372036854775809", "9223372036854775807x", "1e5", "0x1f"};
    for (size_t i = 0; i < sizeof fixed / sizeof *fixed; i++) {
        char *e1, *e2;
        long a = strtol(fixed[i], &e1, 10), b = lex_strtol10(fixed[i], &e2);
        if (a != b || e1 != e2)
            fail_msg("'%s': strtol %ld (end +%td), lex_strtol10 %ld (end +%td)", fixed[i], a, e1 - fixed[i], b,
                     e2 - fixed[i]);
    }
    Rng rng = {77};
    char buf[64];
    for (int i = 0; i < 200000; i++) {
        uint64_t r = rng_next(&rng);
        int n = 0, digits = (int)(r % 22);
        if ((r >> 8) % 3 == 0)
            buf[n++] = (r >> 10) & 1 ? '-' : '+';
        for (int k = 0; k < digits; k++)
            buf[n++] = (char)('0' + rng_next(&rng) % 10);
        if ((r >> 12) & 1)
            buf[n++] = '/';
        buf[n] = 0;
        char *e1, *e2;
        long a = strtol(buf, &e1, 10), b = lex_strtol10(buf, &e2);
        if (a != b || e1 != e2)
            fail_msg("'%s': strtol %ld, lex_strtol10 %ld", buf, a, b);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(numbers_match_strtod),
        cmocka_unit_test(long_matches_strtol),
        cmocka_unit_test(strtol10_matches_strtol),
    };
    return cmocka_run_group_tests_name("lex", tests, NULL, NULL);
}

/* helpers.h - small utilities shared by the unit tests (cmocka). */
#ifndef LANRAY_TEST_HELPERS_H
#define LANRAY_TEST_HELPERS_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <unistd.h>

#include <cmocka.h>

/* cmocka's macro casts its arguments unparenthesised, so (float)a / b
 * promotes back to double in a double build (-Wdouble-promotion) */
#undef assert_float_equal
#define assert_float_equal(a, b, epsilon) \
    _assert_float_equal((float)(a), (float)(b), (float)(epsilon), __FILE__, __LINE__)

#include "base/simd.h"
#include "base/vec.h"

/* 1 in a sanitizer's build (make check-asan, check-tsan; gcc says so): a
 * test that repeats one computation over a large input only for its
 * numbers takes a part of it there, where it runs several times slower;
 * the plain pass takes all of it (the same code). */
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define TEST_SANITIZED 1
#else
#define TEST_SANITIZED 0
#endif

/* Each SIMD path this build and CPU have, forced in turn:
 *     for (int path = -1; simd_next(&path);) { ... }
 * and after the last, the path in use before the first again. */
static inline int simd_next(int *path)
{
    static SimdPath before;
    if (*path < 0)
        before = simd_path();
    while (++*path < SIMD_PATH_COUNT)
        if (simd_force((SimdPath)*path) == 0)
            return 1;
    simd_force(before);
    return 0;
}

/* Deterministic xorshift generator: tests must be repeatable. */
typedef struct {
    uint64_t s;
} Rng;

static inline uint64_t rng_next(Rng *r)
{
    r->s ^= r->s << 13;
    r->s ^= r->s >> 7;
    r->s ^= r->s << 17;
    return r->s;
}
static inline real rng_real(Rng *r, real lo, real hi)
{
    return lo + (hi - lo) * (real)((double)(rng_next(r) >> 11) * (1.0 / 9007199254740992.0));
}
static inline vec3 rng_vec(Rng *r, real lo, real hi) { return v3(rng_real(r, lo, hi), rng_real(r, lo, hi), rng_real(r, lo, hi)); }
static inline vec3 rng_dir(Rng *r)
{
    for (;;) {
        vec3 v = rng_vec(r, -1, 1);
        real l = v3_dot(v, v);
        if (l > R(1e-4) && l <= 1)
            return v3_scale(v, R(1) / sqrt(l));
    }
}

static char test_tmpdir_path[64];

/* Removes path and, for a directory, what it holds. */
static inline void test_rm_tree(const char *path)
{
    DIR *d = opendir(path);
    if (d) {
        struct dirent *e;
        while ((e = readdir(d)))
            if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) {
                char sub[1024];
                if (snprintf(sub, sizeof sub, "%.700s/%.300s", path, e->d_name) < (int)sizeof sub)
                    test_rm_tree(sub);
            }
        closedir(d);
    }
    remove(path);
}

/* The test's temporary directory goes when the test ends. */
static inline void test_tmpdir_remove(void)
{
    if (test_tmpdir_path[0])
        test_rm_tree(test_tmpdir_path);
}

/* A fresh temporary directory for a test's files, removed at exit. */
static inline const char *test_tmpdir(void)
{
    if (!test_tmpdir_path[0]) {
        snprintf(test_tmpdir_path, sizeof test_tmpdir_path, "/tmp/lanray-test-XXXXXX");
        if (!mkdtemp(test_tmpdir_path))
            abort();
        atexit(test_tmpdir_remove);
    }
    return test_tmpdir_path;
}

static inline void test_write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static inline int file_exists(const char *path) { return access(path, F_OK) == 0; }

#define assert_contains(haystack, needle)                                                           \
    do {                                                                                            \
        if (!strstr((haystack), (needle)))                                                          \
            fail_msg("expected \"%s\" in \"%s\"", (needle), (haystack));                            \
    } while (0)

#endif

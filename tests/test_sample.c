/* test_sample.c - the sampling numbers (base/sample.h): bit reversal,
 * Owen scrambling, the scrambled Sobol points' stratification and the
 * sample budget's shares. */
#include "helpers.h"

#include "base/sample.h"
#include "base/sample_lanes.h"
#include "base/simd.h"

static uint32_t reverse_by_loop(uint32_t x)
{
    uint32_t r = 0;
    for (int b = 0; b < 32; b++)
        r |= ((x >> b) & 1u) << (31 - b);
    return r;
}

static void reverse_mirrors_the_bits(void **state)
{
    (void)state;
    assert_int_equal(sample_reverse(1u), 0x80000000u);
    assert_int_equal(sample_reverse(0x0000000fu), 0xf0000000u);
    Rng rng = {7};
    for (int i = 0; i < 100000; i++) {
        uint32_t x = (uint32_t)rng_next(&rng);
        assert_int_equal(sample_reverse(x), reverse_by_loop(x));
    }
}

/* Owen scrambling permutes the fractions' leading bits among themselves:
 * the 2^k fractions that differ only in their top k bits go to 2^k
 * different top-k prefixes, for any seed. */
static void owen_permutes_each_prefix_level(void **state)
{
    (void)state;
    for (uint32_t seed = 1; seed < 40; seed++)
        for (int k = 1; k <= 12; k++) {
            uint8_t seen[4096] = {0};
            for (uint32_t p = 0; p < (1u << k); p++) {
                uint32_t top = sample_owen(p << (32 - k), sample_hash(seed)) >> (32 - k);
                assert_int_equal(seen[top], 0);
                seen[top] = 1;
            }
        }
}

/* Every aligned block of 2^k points of a sequence is a (0,k,2)-net: for
 * each split of k into a + b, every box of 2^-a by 2^-b holds one point. */
static void sobol_blocks_are_nets(void **state)
{
    (void)state;
    for (uint32_t seed = 0; seed < 24; seed++)
        for (int k = 0; k <= 10; k++)
            for (uint32_t first = 0; first < (4u << k); first += 1u << k) {
                uint32_t n = 1u << k;
                for (int a = 0; a <= k; a++) {
                    uint8_t seen[1024] = {0};
                    for (uint32_t i = first; i < first + n; i++) {
                        real u, v;
                        sample_sobol2(i, sample_mix(0x1234u, seed), &u, &v);
                        assert_true(u >= 0 && u < 1 && v >= 0 && v < 1);
                        uint32_t cu = (uint32_t)(u * (real)(1u << a)), cv = (uint32_t)(v * (real)(1u << (k - a)));
                        uint32_t box = (cu << (k - a)) | cv;
                        assert_int_equal(seen[box], 0);
                        seen[box] = 1;
                    }
                }
            }
}

/* Two seeds give unrelated sequences: the points of one against the
 * other's are uncorrelated (|r| small over 4096 points), while a seed
 * against itself is the same sequence. */
static void sobol_seeds_are_independent(void **state)
{
    (void)state;
    const int n = 4096;
    double su = 0, sv = 0, suu = 0, svv = 0, suv = 0;
    for (int i = 0; i < n; i++) {
        real u1, v1, u2, v2, u3, v3_;
        sample_sobol2((uint32_t)i, 11u, &u1, &v1);
        sample_sobol2((uint32_t)i, 12u, &u2, &v2);
        sample_sobol2((uint32_t)i, 11u, &u3, &v3_);
        assert_true(u1 == u3 && v1 == v3_);
        double a = (double)u1, b = (double)u2;
        su += a, sv += b, suu += a * a, svv += b * b, suv += a * b;
    }
    double cov = suv / n - su / n * sv / n, r = cov / sqrt((suu / n - su / n * su / n) * (svv / n - sv / n * sv / n));
    assert_true(fabs(r) < 0.06);
}

/* A pixel's K points spread over its rays: ceil(K / rays), at least one. */
static void shares_add_up_to_the_budget(void **state)
{
    (void)state;
    assert_int_equal(sample_share(9, 1), 9);
    assert_int_equal(sample_share(9, 4), 3);
    assert_int_equal(sample_share(9, 9), 1);
    assert_int_equal(sample_share(9, 16), 1);
    assert_int_equal(sample_share(1, 1), 1);
    for (uint32_t k = 1; k < 300; k++)
        for (uint32_t c = 1; c < 300; c++) {
            uint32_t m = sample_share(k, c);
            assert_true(m >= 1 && m * c >= k && (m == 1 || (m - 1) * c < k));
        }
}

/* Eight lanes of Sobol points on every SIMD path this CPU has are
 * sample_sobol_point's, bit for bit, for random sequences and indices
 * (the AVX2 path's byte shuffles and nibble tables reverse each lane's
 * bits; a lane's scrambles must not leak into another's). */
static void lanes_equal_single_points(void **state)
{
    (void)state;
    uint32_t x = 12345;
    for (int path = -1; simd_next(&path);) {
        for (int round = 0; round < 2000; round++) {
            SampleLanes sl;
            for (int k = 0; k < SAMPLE_LANES; k++) {
                sl.seq_index[k] = x = sample_hash(x + 1), sl.seq_first[k] = x = sample_hash(x + 1);
                sl.seq_second[k] = x = sample_hash(x + 1);
                sl.index[k] = round < 1000 ? (uint32_t)(round * SAMPLE_LANES + k) : (x = sample_hash(x + 1));
            }
            sample_sobol_lanes(&sl);
            for (int k = 0; k < SAMPLE_LANES; k++) {
                const SampleSobol q = {sl.seq_index[k], sl.seq_first[k], sl.seq_second[k]};
                real u, v;
                sample_sobol_point(&q, sl.index[k], &u, &v);
                if (sample_unit(sl.u[k]) != u || sample_unit(sl.v[k]) != v)
                    fail_msg("%s: lane %d of round %d: (%.9g, %.9g), alone (%.9g, %.9g)", simd_name((SimdPath)path), k,
                             round, (double)sample_unit(sl.u[k]), (double)sample_unit(sl.v[k]), (double)u, (double)v);
            }
        }
    }
}

/* A bounce's dimensions drawn at once (sample_draw_lanes) are the
 * numbers each gives alone: sample_mix's seed, sample_sobol_seq's
 * scrambles, sample_sobol_point's u and v and sample_sobol_first's u, to
 * the bit, on every SIMD path. */
static void draw_lanes_equal_single_draws(void **state)
{
    (void)state;
    uint32_t x = 777;
    for (int path = -1; simd_next(&path);) {
        for (int round = 0; round < 2000; round++) {
            uint32_t dim[SAMPLE_LANES], u[SAMPLE_LANES], v[SAMPLE_LANES];
            const uint32_t key = x = sample_hash(x + 1);
            const uint32_t index = round < 1000 ? (uint32_t)round : (x = sample_hash(x + 1));
            for (int k = 0; k < SAMPLE_LANES; k++)
                dim[k] = round % 2 ? (uint32_t)k + 1 : (x = sample_hash(x + 1));
            sample_draw_lanes(key, index, dim, u, v);
            for (int k = 0; k < SAMPLE_LANES; k++) {
                const SampleSobol q = sample_sobol_seq(sample_mix(key, dim[k]));
                real pu, pv;
                sample_sobol_point(&q, index, &pu, &pv);
                const real first = sample_sobol_first(&q, index);
                if (sample_unit(u[k]) != pu || sample_unit(v[k]) != pv || sample_unit(u[k]) != first)
                    fail_msg("%s: lane %d of round %d: (%.9g, %.9g), alone (%.9g, %.9g)", simd_name((SimdPath)path), k,
                             round, (double)sample_unit(u[k]), (double)sample_unit(v[k]), (double)pu, (double)pv);
            }
        }
    }
}

/* A pixel's cells made at once (sample_grid_cells, as the renderer takes
 * a path-traced pixel's samples) are sample_grid_cell's one by one, on
 * every SIMD path, for every count (fewer than the lanes, a whole number
 * of lanes and between), start and grid size, m 0 included. */
static void grid_cells_equal_single_cells(void **state)
{
    (void)state;
    uint32_t x = 4242;
    for (int path = -1; simd_next(&path);) {
        for (int round = 0; round < 600; round++) {
            const SampleSobol q = sample_grid_seq(x = sample_hash(x + 1));
            const int m = round % 6;
            const uint32_t count = 1 + (uint32_t)round % 40, first = round % 3 ? (uint32_t)round : (x = sample_hash(x + 1));
            uint32_t i[40], j[40]; /* count rounded up to the lanes */
            sample_grid_cells(&q, first, count, m, i, j);
            for (uint32_t k = 0; k < count; k++) {
                uint32_t a, b;
                sample_grid_cell(&q, first + k, m, &a, &b);
                if (a != i[k] || b != j[k])
                    fail_msg("%s: sample %u of %u from %u, m %d: cell (%u, %u), alone (%u, %u)",
                             simd_name((SimdPath)path), k, count, first, m, i[k], j[k], a, b);
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reverse_mirrors_the_bits),
        cmocka_unit_test(owen_permutes_each_prefix_level),
        cmocka_unit_test(sobol_blocks_are_nets),
        cmocka_unit_test(sobol_seeds_are_independent),
        cmocka_unit_test(shares_add_up_to_the_budget),
        cmocka_unit_test(lanes_equal_single_points),
        cmocka_unit_test(draw_lanes_equal_single_draws),
        cmocka_unit_test(grid_cells_equal_single_cells),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

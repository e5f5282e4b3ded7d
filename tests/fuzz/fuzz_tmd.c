/* fuzz_tmd.c - the .tmd reader on arbitrary bytes; an accepted model is
 * prepared as a scene prepares it (its wide tree, a cutout's trees) and
 * traced, so that whatever passes validation is also safe to traverse.
 * A version-5 file carries its length and a checksum, which random bytes
 * almost never match: each input is also read sealed (those two fields
 * made right), so that the fuzzer reaches the checks behind them. */
#include "fuzz.h"
#include "model/tmd.h"

static void read_model(const uint8_t *data, size_t size)
{
    Model *m;
    if (tmd_decode(data, size, "fuzz.tmd", &m, NULL) != 0)
        return;
    if (model_prepare_simd(m, NULL) != 0) { /* the wide tree and a cutout's walks, as a scene's */
        model_destroy(m);
        return;
    }
    for (int i = 0; i < 16; i++) {
        vec3 o = v3((real)(i % 4) - R(1.5), (real)(i / 4) - R(1.5), -10);
        Ray r = ray_make(o, v3(R(0.01) * (real)i, R(0.02), 1), 0, REAL_INF);
        ModelHit h;
        model_intersect(m, &r, REAL_INF, 0, &h);
        model_occluded(m, &r, REAL_INF);
    }
    model_destroy(m);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    read_model(data, size);
    if (size < TMD_HEADER_BYTES)
        return 0;
    uint8_t *sealed = malloc(size);
    if (!sealed)
        return 0;
    memcpy(sealed, data, size);
    uint32_t len = (uint32_t)size, crc;
    memcpy(sealed + TMD_LENGTH_AT, &len, 4);
    crc = tmd_checksum(sealed, size);
    memcpy(sealed + TMD_CHECKSUM_AT, &crc, 4);
    read_model(sealed, size);
    free(sealed);
    return 0;
}

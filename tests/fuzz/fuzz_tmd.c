/* fuzz_tmd.c - the .tmd reader on arbitrary bytes; an accepted model is
 * traced, so that whatever passes validation is also safe to traverse. */
#include "fuzz.h"
#include "model/tmd.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    Model *m;
    if (tmd_decode(data, size, "fuzz.tmd", &m, NULL) != 0)
        return 0;
    for (int i = 0; i < 16; i++) {
        vec3 o = v3((real)(i % 4) - R(1.5), (real)(i / 4) - R(1.5), -10);
        Ray r = ray_make(o, v3(R(0.01) * (real)i, R(0.02), 1), 0, REAL_INF);
        ModelHit h;
        model_intersect(m, &r, REAL_INF, 0, &h);
        model_occluded(m, &r, REAL_INF);
    }
    model_destroy(m);
    return 0;
}

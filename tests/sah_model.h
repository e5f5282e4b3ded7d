/* sah_model.h - a test's model from the mesh it made: the SAH tree (the
 * renderer's default), the mesh freed. */
#ifndef LANRAY_TEST_SAH_MODEL_H
#define LANRAY_TEST_SAH_MODEL_H

#include <stdio.h>
#include <stdlib.h>

#include "model/model.h"

static inline Model *sah_model(Mesh *mesh)
{
    Model *model;
    Err err;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    if (model_from_mesh(&model, mesh, &opt, &err)) {
        fprintf(stderr, "sah_model: %s\n", err.msg);
        abort();
    }
    mesh_free(mesh);
    return model;
}

#endif

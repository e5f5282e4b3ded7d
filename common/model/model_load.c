/* model_load.c - see model_load.h. */
#include "model/model_load.h"

#include <string.h>

#include "model/import.h"
#include "model/obj.h"
#include "model/tmd.h"

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

int model_load_knows(const char *path)
{
    return ends_with(path, ".obj") || ends_with(path, ".tmd") || import_knows(path);
}

int model_load(const char *path, const BvhOptions *opt, int rebuild, int smooth, Model **out, Err *err)
{
    *out = NULL;
    if (ends_with(path, ".obj")) {
        Mesh mesh;
        ObjOptions oo = {.smooth = smooth};
        if (obj_read(path, &oo, &mesh, NULL, err))
            return -1;
        int rc = model_from_mesh(out, &mesh, opt, err);
        mesh_free(&mesh);
        return rc ? err_prefix(err, "%s", path) : 0;
    }
    if (import_knows(path)) { /* PLY, STL, glTF, ... (import.h) */
        Mesh mesh;
        if (smooth)
            return err_set(err, "%s: 'smooth' applies to OBJ models", path);
        if (import_read(path, NULL, &mesh, NULL, err))
            return -1;
        int rc = model_from_mesh(out, &mesh, opt, err);
        mesh_free(&mesh);
        return rc ? err_prefix(err, "%s", path) : 0;
    }
    if (!ends_with(path, ".tmd"))
        return err_set(err, "model file '%s' must end in .tmd, .obj, or a format the importer reads (.ply, .stl, .gltf, .glb, ...)", path);
    if (smooth)
        return err_set(err, "%s: 'smooth' applies to OBJ models; convert with obj2tmd --smooth", path);
    if (tmd_read(path, out, err))
        return -1;
    if (rebuild && model_rebuild(*out, opt, err)) {
        model_destroy(*out);
        *out = NULL;
        return err_prefix(err, "%s", path);
    }
    return 0;
}

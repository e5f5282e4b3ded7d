/* model_load.c - see model_load.h. */
#include "model/model_load.h"

#include "base/fileio.h"
#include "model/import.h"
#include "model/obj.h"
#include "model/tmd.h"

ModelFormat model_format(const char *path)
{
    if (file_has_suffix(path, ".obj"))
        return MODEL_FORMAT_OBJ;
    if (file_has_suffix(path, ".tmd"))
        return MODEL_FORMAT_TMD;
    return import_knows(path) ? MODEL_FORMAT_IMPORT : MODEL_FORMAT_UNKNOWN;
}

static void (*load_warn)(void *ctx, const char *msg);
static void *load_warn_ctx;

void model_load_warnings(void (*warn)(void *ctx, const char *msg), void *ctx)
{
    load_warn = warn, load_warn_ctx = ctx;
}

int model_load_knows(const char *path) { return model_format(path) != MODEL_FORMAT_UNKNOWN; }

int model_load(const char *path, const BvhOptions *opt, int rebuild, int smooth, Model **out, Err *err)
{
    *out = NULL;
    const ModelFormat f = model_format(path);
    if (f == MODEL_FORMAT_OBJ) {
        Mesh mesh;
        ObjOptions oo = {.smooth = smooth, .warn = load_warn, .warn_ctx = load_warn_ctx};
        if (obj_read(path, &oo, &mesh, NULL, err))
            return -1;
        int rc = model_from_mesh(out, &mesh, opt, err);
        mesh_free(&mesh);
        return rc ? err_prefix(err, "%s", path) : 0;
    }
    if (f == MODEL_FORMAT_IMPORT) { /* PLY, STL, glTF, ... (import.h) */
        Mesh mesh;
        ObjOptions oo = {.smooth = smooth, .warn = load_warn, .warn_ctx = load_warn_ctx};
        if (import_read(path, &oo, &mesh, NULL, err))
            return -1;
        int rc = model_from_mesh(out, &mesh, opt, err);
        mesh_free(&mesh);
        return rc ? err_prefix(err, "%s", path) : 0;
    }
    if (f == MODEL_FORMAT_UNKNOWN)
        return err_set(err, "model file '%s' must end in .tmd, .obj, or a format the importer reads (.ply, .stl, .gltf, .glb, ...; docs/models.md)", path);
    if (smooth)
        return err_set(err, "%s: 'smooth' applies to models converted on load; convert with obj2tmd --smooth", path);
    if (tmd_read(path, out, err))
        return -1;
    if (rebuild && model_rebuild(*out, opt, err)) {
        model_destroy(*out);
        *out = NULL;
        return err_prefix(err, "%s", path);
    }
    return 0;
}

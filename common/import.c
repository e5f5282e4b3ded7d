/* import.c - see import.h. */
#include "import.h"

#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <ctype.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define IMPORT_MAX_TRIANGLES (1u << 26) /* BVH_MAX_PRIMS */

static const char *const formats[] = {".ply", ".stl", ".gltf", ".glb", ".fbx", ".dae", ".3ds", ".off", ".lwo", ".x", NULL};

static const char *extension(const char *path)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    return dot && (!slash || dot > slash) ? dot : "";
}

int import_knows(const char *path)
{
    const char *e = extension(path);
    char low[16];
    size_t n = strlen(e);
    if (n == 0 || n >= sizeof low)
        return 0;
    for (size_t i = 0; i <= n; i++)
        low[i] = (char)tolower((unsigned char)e[i]);
    for (int i = 0; formats[i]; i++)
        if (strcmp(low, formats[i]) == 0)
            return 1;
    return 0;
}

static Material import_material(const struct aiMaterial *am)
{
    Material m = material_default();
    struct aiColor4D c;
    if (aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS)
        m.kd = v3(c.r, c.g, c.b);
    if (aiGetMaterialColor(am, AI_MATKEY_COLOR_SPECULAR, &c) == aiReturn_SUCCESS)
        m.ks = v3(c.r, c.g, c.b);
    ai_real s;
    if (aiGetMaterialFloat(am, AI_MATKEY_SHININESS, &s) == aiReturn_SUCCESS && s >= 0)
        m.shininess = s;
    for (int k = 0; k < 3; k++) /* files can hold anything: keep what shading accepts */
        if (!(m.kd.e[k] >= 0) || !isfinite(m.kd.e[k]) || !(m.ks.e[k] >= 0) || !isfinite(m.ks.e[k]))
            return material_default();
    if (!isfinite(m.shininess))
        m.shininess = 1;
    return m;
}

/* Assimp 5.2.5's PLY reader spins on some malformed headers (an element
 * line cut short kept fuzz_import busy past its timeout), so a PLY header
 * is checked here first: it ends with end_header within the first 64 KiB,
 * and every element line is "element NAME COUNT" with a count that the
 * file's size could hold (at least one byte per element). */
#define PLY_HEADER_MAX 65536

static int ply_header_check(const char *head, size_t n, uint64_t file_size, const char *name, Err *err)
{
    if (n < 4 || memcmp(head, "ply", 3) != 0 || (head[3] != '\n' && head[3] != '\r'))
        return err_set(err, "%s: not a PLY file (no 'ply' line)", name);
    size_t i = 0;
    uint64_t elements = 0;
    while (i < n) {
        size_t e = i;
        while (e < n && head[e] != '\n')
            e++;
        if (e == n)
            break;
        char line[256];
        size_t len = e - i < sizeof line - 1 ? e - i : sizeof line - 1;
        memcpy(line, head + i, len);
        line[len] = 0;
        if (len && line[len - 1] == '\r')
            line[--len] = 0;
        i = e + 1;
        if (strcmp(line, "end_header") == 0)
            return elements > file_size ? err_set(err, "%s: PLY header claims %llu elements in a file of %llu bytes", name,
                                                  (unsigned long long)elements, (unsigned long long)file_size)
                                        : 0;
        if (strncmp(line, "element", 7) == 0) {
            char ename[128];
            unsigned long long count;
            char extra;
            if (sscanf(line, "element %127s %llu %c", ename, &count, &extra) != 2)
                return err_set(err, "%s: PLY header: malformed line '%s'", name, line);
            elements += count;
            if (elements > file_size)
                return err_set(err, "%s: PLY header claims %llu elements in a file of %llu bytes", name,
                               (unsigned long long)elements, (unsigned long long)file_size);
        }
    }
    return err_set(err, "%s: PLY header without end_header in its first %d bytes", name, PLY_HEADER_MAX);
}

static int is_ply(const char *path)
{
    const char *e = extension(path);
    return strcmp(e, ".ply") == 0 || strcmp(e, ".PLY") == 0;
}

#define IMPORT_FLAGS (aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType | aiProcess_ValidateDataStructure)

static int import_scene(const struct aiScene *sc, const char *path, int stl, Mesh *out, ImportStats *st, Err *err);

int import_read(const char *path, Mesh *out, ImportStats *st, Err *err)
{
    ImportStats local;
    if (!st)
        st = &local;
    memset(st, 0, sizeof *st);
    memset(out, 0, sizeof *out);
    if (!import_knows(path))
        return err_set(err, "%s: not a format the importer reads (PLY, STL, glTF, ...)", path);
    if (is_ply(path)) {
        FILE *f = fopen(path, "rb");
        if (!f)
            return err_set(err, "%s: cannot open", path);
        char head[PLY_HEADER_MAX];
        size_t n = fread(head, 1, sizeof head, f);
        int seek = fseek(f, 0, SEEK_END);
        long size = seek == 0 ? ftell(f) : -1;
        fclose(f);
        if (size < 0 || ply_header_check(head, n, (uint64_t)size, path, err))
            return size < 0 ? err_set(err, "%s: cannot read", path) : -1;
    }
    const struct aiScene *sc = aiImportFile(path, IMPORT_FLAGS);
    if (!sc)
        return err_set(err, "%s: %s", path, aiGetErrorString());
    const char *e = extension(path);
    int rc = import_scene(sc, path, strcmp(e, ".stl") == 0 || strcmp(e, ".STL") == 0, out, st, err);
    aiReleaseImport(sc);
    return rc;
}

int import_read_memory(const void *data, size_t len, const char *hint, const char *name, Mesh *out,
                       ImportStats *st, Err *err)
{
    ImportStats local;
    if (!st)
        st = &local;
    memset(st, 0, sizeof *st);
    memset(out, 0, sizeof *out);
    if (len > UINT32_MAX)
        return err_set(err, "%s: too large", name);
    if (strcmp(hint, "ply") == 0 &&
        ply_header_check(data, len < PLY_HEADER_MAX ? len : PLY_HEADER_MAX, (uint64_t)len, name, err))
        return -1;
    const struct aiScene *sc = aiImportFileFromMemory(data, (unsigned)len, IMPORT_FLAGS, hint);
    if (!sc)
        return err_set(err, "%s: %s", name, aiGetErrorString());
    int rc = import_scene(sc, name, strcmp(hint, "stl") == 0, out, st, err);
    aiReleaseImport(sc);
    return rc;
}

/* The triangles of an imported scene into *out (stats counted). */
static int import_scene(const struct aiScene *sc, const char *path, int stl, Mesh *out, ImportStats *st, Err *err)
{
    int has_n = 0, has_t = 0;
    unsigned long faces = 0;
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        const struct aiMesh *am = sc->mMeshes[i];
        if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
            continue;
        has_n |= am->mNormals != NULL && !stl;
        has_t |= am->mTextureCoords[0] != NULL;
        faces += am->mNumFaces;
    }
    int rc = 0;
    if (faces > IMPORT_MAX_TRIANGLES)
        rc = err_set(err, "%s: %lu triangles exceed the limit of %u", path, faces, IMPORT_MAX_TRIANGLES);
    /* a file without materials gets one that Assimp makes up, unnamed (PLY,
     * glTF) or "DefaultMaterial" (STL): no material then, as an OBJ
     * without usemtl, so the scene's default applies */
    int has_m = sc->mNumMaterials > 1;
    if (sc->mNumMaterials == 1) {
        struct aiString name;
        has_m = aiGetMaterialString(sc->mMaterials[0], AI_MATKEY_NAME, &name) == aiReturn_SUCCESS && name.length &&
                strcmp(name.data, AI_DEFAULT_MATERIAL_NAME) != 0;
    }
    if (rc == 0)
        rc = mesh_init(out, has_n, has_t, has_m, err);
    for (unsigned i = 0; rc == 0 && has_m && i < sc->mNumMaterials; i++)
        rc = mesh_add_material(out, import_material(sc->mMaterials[i]), err);
    for (unsigned i = 0; rc == 0 && i < sc->mNumMeshes; i++) {
        const struct aiMesh *am = sc->mMeshes[i];
        st->meshes++;
        st->vertices += am->mNumVertices;
        for (unsigned f = 0; rc == 0 && f < am->mNumFaces; f++) {
            const struct aiFace *fc = &am->mFaces[f];
            if (fc->mNumIndices == 1) {
                st->points++;
                continue;
            }
            if (fc->mNumIndices == 2) {
                st->lines++;
                continue;
            }
            if (fc->mNumIndices != 3)
                continue; /* Triangulate leaves none */
            vec3 p[3], n[3];
            real uv[6] = {0};
            int bad = 0;
            for (int k = 0; k < 3; k++) {
                unsigned v = fc->mIndices[k];
                if (v >= am->mNumVertices) {
                    bad = 1;
                    break;
                }
                p[k] = v3(am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z);
                if (has_n)
                    n[k] = am->mNormals && !stl ? v3(am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z)
                                                : v3(0, 0, 0);
                if (has_t && am->mTextureCoords[0]) {
                    uv[2 * k] = am->mTextureCoords[0][v].x;
                    uv[2 * k + 1] = am->mTextureCoords[0][v].y;
                }
            }
            if (bad) {
                rc = err_set(err, "%s: mesh %u face %u: vertex index out of range", path, i, f);
                break;
            }
            if (!v3_is_finite(p[0]) || !v3_is_finite(p[1]) || !v3_is_finite(p[2])) {
                rc = err_set(err, "%s: mesh %u face %u: a coordinate that is not a finite number", path, i, f);
                break;
            }
            if (mesh_tri_is_degenerate(p)) {
                st->degenerate++;
                continue;
            }
            if (has_n) { /* a face without usable normals gets its geometric one, as the OBJ reader does */
                vec3 fn = v3_norm(v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0])));
                for (int k = 0; k < 3; k++) {
                    n[k] = v3_norm(n[k]);
                    if (!(v3_dot(n[k], n[k]) > R(0.5)))
                        n[k] = fn;
                }
            }
            uint32_t mat = has_m && am->mMaterialIndex < sc->mNumMaterials ? am->mMaterialIndex : 0;
            rc = mesh_add(out, p, has_n ? n : NULL, has_t ? uv : NULL, mat, err);
        }
    }
    if (rc) {
        mesh_free(out);
        return -1;
    }
    st->triangles = out->tri_count;
    return 0;
}

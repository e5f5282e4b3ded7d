/* import.c - see import.h. */
#include "model/import.h"

#include "base/dmath.h"
#include "model/smooth.h"

#include <assimp/GltfMaterial.h>
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <ctype.h>
#include <math.h>
#include <errno.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "base/cursor.h"
#include "model/import_extensions.h"
#include "model/import_texture.h"

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
    if (strcmp(low, ".obj") == 0 || strcmp(low, ".tmd") == 0) /* lanray's own readers */
        return 0;
    for (int i = 0; formats[i]; i++)
        if (strcmp(low, formats[i]) == 0)
            return 1;
    /* the rest of what Assimp reads (.blend, .ac, .ase, .ms3d, .nff, ...):
     * less common, read in the child as the others are */
    return aiIsExtensionSupported(low) == AI_TRUE;
}

/* A material's colour key, where the file sets it to finite, non-negative values. */
static int import_colour(const struct aiMaterial *am, const char *key, unsigned type, unsigned idx, vec3 *out)
{
    struct aiColor4D c;
    if (aiGetMaterialColor(am, key, type, idx, &c) != aiReturn_SUCCESS)
        return 0;
    const vec3 v = v3(c.r, c.g, c.b);
    for (int k = 0; k < 3; k++) /* files can hold anything: keep what shading accepts */
        if (!(v.e[k] >= 0) || !isfinite(v.e[k]))
            return 0;
    *out = v;
    return 1;
}

/* A material's number key, where the file sets it within [lo, hi]. */
static int import_number(const struct aiMaterial *am, const char *key, unsigned type, unsigned idx, real lo, real hi,
                         real *out)
{
    ai_real v;
    if (aiGetMaterialFloat(am, key, type, idx, &v) != aiReturn_SUCCESS || !((real)v >= lo && (real)v <= hi))
        return 0;
    *out = (real)v;
    return 1;
}

/* A metal-roughness material's factors (glTF's, FBX's PBR), and whether
 * a texture scales them (then import_materials looks for it). */
typedef struct {
    vec3 base;
    real metal, rough;
    int mapped;
    int applied; /* the material is a metal by them (import_metal_as made it) */
    int pbr;     /* the file gives them (a metallic factor) */
    int plain;   /* glTF's defaults alone: white, metallic 1, roughness 1, no texture */
} MetalFactors;

/* The factors in lanray's terms: the metal's share of the base colour
 * reflects as a mirror of the file's roughness (the GGX roughness
 * scene2cycles writes for a rough mirror), with a Phong highlight of the
 * same colour for the lights (material_phong_exponent); the rest is
 * diffuse.  A non-metal keeps no highlight, as before: a dielectric's 4%
 * would brighten every rough surface of a Whitted frame.  With a
 * metal-roughness texture (f->mapped: it says where, texel by texel) kd
 * keeps the whole base colour and kr the factor's share of it: a hit
 * takes the texel's share of each (trace.c). */
static void import_metal_as(MetalFactors *f, Material *m)
{
    f->applied = 1;
    m->kd = f->mapped ? f->base : v3_scale(f->base, R(1) - f->metal);
    m->kr = v3_scale(f->base, f->metal);
    /* glTF's metal brightens towards white at grazing angles (Schlick, its F0 the base colour) */
    m->kre = material_reflects(m) ? v3_splat(f->metal) : v3_splat(R(0));
    m->roughness = f->rough;
    m->ks = m->kr;
    m->shininess = material_phong_exponent(f->rough);
}

/* Reads a metal's factors into *f and applies them, unless a texture
 * scales them (f->mapped: applied once it is found). */
static void import_metal(const struct aiMaterial *am, vec3 base, Material *m, MetalFactors *f)
{
    *f = (MetalFactors){base, 0, 1, 0, 0, 0, 0};
    if (!import_number(am, AI_MATKEY_METALLIC_FACTOR, 0, 1, &f->metal))
        return;
    f->pbr = 1;
    import_number(am, AI_MATKEY_ROUGHNESS_FACTOR, 0, 1, &f->rough);
    if (f->metal <= 0)
        return;
    /* a metalness texture says, texel by texel, where the factor applies
     * (most often nowhere: the factor left at glTF's default of 1); until
     * it is found, the material stays as it was, not all metal.  And glTF's
     * defaults alone (white, metallic 1, roughness 1, no texture: what a
     * primitive without a material gets) stay white diffuse, as geometry
     * without materials shows elsewhere in lanray. */
    f->mapped = aiGetMaterialTextureCount(am, aiTextureType_METALNESS) > 0 ||
                aiGetMaterialTextureCount(am, aiTextureType_UNKNOWN) > 0;
    f->plain = !f->mapped && f->metal == 1 && f->rough == 1 && base.x == 1 && base.y == 1 && base.z == 1;
    if (!f->mapped && !f->plain)
        import_metal_as(f, m);
}

/* Whether a material is a glTF's (Assimp gives those an alpha mode), the
 * mode in *mode. */
static int gltf_material(const struct aiMaterial *am, struct aiString *mode)
{
    return aiGetMaterialString(am, "$mat.gltf.alphaMode", 0, 0, mode) == aiReturn_SUCCESS;
}

/* KHR_materials_volume (Assimp reads it): light that crosses attenuation
 * distance d inside keeps attenuation colour c of itself, so the
 * Beer-Lambert absorption is -ln(c) / d a unit, per channel (a channel of
 * c at 0 absorbs as one of 1e-6 would).  Only where the file gives a
 * finite distance; in the model's units, as its distances are. */
static void import_volume(const struct aiMaterial *am, Material *m)
{
    vec3 c;
    real d;
    if (!import_number(am, AI_MATKEY_VOLUME_ATTENUATION_DISTANCE, R(1e-9), R(1e30), &d) ||
        !import_colour(am, AI_MATKEY_VOLUME_ATTENUATION_COLOR, &c))
        return;
    for (int k = 0; k < 3; k++)
        m->absorb.e[k] = c.e[k] >= R(1) ? R(0) : -log(real_max(c.e[k], R(1e-6))) / d;
}

/* A glTF material's emission (its emissive factor; Assimp 5.2 does not
 * read KHR_materials_emissive_strength: import_extensions.h applies it
 * after), transmission
 * (KHR_materials_transmission: glass of the file's index, or 1.5, tinted by
 * the base colour, frosted by the material's roughness; the dielectric share's, glTF says, so a metal by factors
 * f (f->applied) transmits 1 - its metallic of it, and its mirror lies over
 * the glass) and, for alphaMode BLEND, its alpha (a see-through blend, as
 * an MTL's dissolve, of every reflecting term).  Applied over what
 * import_metal_as made, and again after it where a metal-roughness texture
 * makes the material a metal later (import_materials).  Only glTF's: the other formats' emissive
 * and opacity values mean different things to different exporters
 * (COLLADA files of assimp-testmodels say opacity 0 for opaque teapots, a
 * Milkshape jeep an emission of 0.35 for its ambient), and stay unread, as
 * before.  Returns whether any of them applied. */
static int import_optics(const struct aiMaterial *am, vec3 base, const MetalFactors *f, Material *m)
{
    struct aiString mode;
    if (!gltf_material(am, &mode))
        return 0;
    int did = 0;
    vec3 ke;
    real t = 0, opacity = 1;
    if (import_colour(am, AI_MATKEY_COLOR_EMISSIVE, &ke) && v3_max_comp(ke) > 0) {
        m->ke = ke;
        did = 1;
    }
    if (import_number(am, AI_MATKEY_TRANSMISSION_FACTOR, 0, 1, &t) && t > 0) {
        real ior = R(1.5);
        import_number(am, AI_MATKEY_REFRACTI, MATERIAL_IOR_MIN, MATERIAL_IOR_MAX, &ior);
        m->ior = ior;
        m->kt = v3_scale(base, t * (f->applied ? R(1) - f->metal : R(1)));
        m->kd = v3_scale(m->kd, R(1) - t);
        m->roughness = f->pbr ? f->rough : R(0); /* frosted by the file's roughness (glTF's default: 1) */
        import_volume(am, m);
        did = 1;
    } else if (strcmp(mode.data, "BLEND") == 0 && import_number(am, AI_MATKEY_OPACITY, 0, 1, &opacity) && opacity < 1) {
        m->ior = R(1);
        m->kt = v3_splat(R(1) - opacity);
        m->kd = v3_scale(m->kd, opacity);
        m->ks = v3_scale(m->ks, opacity);
        m->kr = v3_scale(m->kr, opacity);
        m->kre = v3_scale(m->kre, opacity);
        m->ke = v3_scale(m->ke, opacity); /* the see-through share emits nothing (Blender's mix with Transparent) */
        did = 1;
    }
    return did;
}

/* A glTF material's clear coat: the specular reflection of its dielectric
 * share (glTF's base is a dielectric of index 1.5 where it is not metal:
 * Fresnel's 4% head on, the base colour diffuse under it), of the
 * material's roughness; 1 - metallic of it for a metal by its factors, all
 * of it where a metal-roughness texture says texel by texel (trace.c's
 * surface_metal takes the texel's metal off).  KHR_materials_clearcoat's
 * coat, where the file has one, in its place (its factor and roughness:
 * the dielectric's own reflection under it is not kept).  None for glass
 * (its Fresnel reflection is its coat), glTF's defaults alone, or other
 * formats (their specular colour is their highlight). */
static void import_coat(const struct aiMaterial *am, const MetalFactors *f, Material *m)
{
    struct aiString mode;
    m->coat = 0, m->coat_roughness = 0;
    if (!f->pbr || f->plain || material_dielectric(m) || !gltf_material(am, &mode))
        return;
    real cc = 0;
    if (import_number(am, AI_MATKEY_CLEARCOAT_FACTOR, 0, 1, &cc) && cc > 0) {
        m->coat = cc;
        import_number(am, AI_MATKEY_CLEARCOAT_ROUGHNESS_FACTOR, 0, 1, &m->coat_roughness);
        return;
    }
    m->coat = f->applied && !f->mapped ? R(1) - f->metal : R(1);
    m->coat_roughness = m->coat > R(0) ? f->rough : R(0);
}

static Material import_material(const struct aiMaterial *am, int *optics, MetalFactors *metal)
{
    Material m = material_default();
    vec3 c;
    if (import_colour(am, AI_MATKEY_COLOR_DIFFUSE, &c))
        m.kd = c;
    if (import_colour(am, AI_MATKEY_COLOR_SPECULAR, &c))
        m.ks = c;
    real s;
    if (import_number(am, AI_MATKEY_SHININESS, 0, 1e6, &s))
        m.shininess = s;
    vec3 base = m.kd;
    import_colour(am, AI_MATKEY_BASE_COLOR, &base);
    import_metal(am, base, &m, metal);
    *optics = import_optics(am, base, metal, &m) || material_reflects(&m);
    import_coat(am, metal, &m);
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

/* Assimp 5.2.5 allocates a GLB chunk's length as its header gives it (a
 * 1.8 KB file claiming a 3.3 GB JSON chunk: fuzz_import's out-of-memory
 * findings), so a GLB's header and chunk headers are checked here first:
 * magic, version 2, a total length that holds the header and a chunk's
 * header, and chunks that fit in the file, up to its end (Assimp reads
 * the JSON chunk whatever the total length says: a total of 0 let a
 * chunk of 2.9 GB through). */
/* Assimp's refusal, in words: its running out of the child's memory cap
 * (child_memory_cap) says what that means. */
static int assimp_failed(const char *name, Err *err)
{
    const char *why = aiGetErrorString();
    if (strstr(why, "bad_alloc"))
        return err_set(err, "%s: the importer ran out of memory reading it (a file that claims more than it holds, "
                            "or a model too big for this machine)", name);
    return err_set(err, "%s: %s", name, why);
}

static int glb_check(FILE *f, uint64_t size, const char *name, Err *err)
{
    uint32_t head[3];
    if (fseek(f, 0, SEEK_SET) != 0 || fread(head, 4, 3, f) != 3 || memcmp(head, "glTF", 4) != 0)
        return err_set(err, "%s: not a GLB file (no glTF header)", name);
    if (head[1] != 2)
        return err_set(err, "%s: GLB version %u, lanray reads version 2", name, head[1]);
    if (head[2] > size || head[2] < 20)
        return err_set(err, "%s: the GLB header says %u bytes, the file has %llu (and a GLB at least 20)", name,
                       head[2], (unsigned long long)size);
    uint64_t at = 12;
    for (int chunk = 0; at + 8 <= size; chunk++) {
        uint32_t ch[2];
        if (fseek(f, (long)at, SEEK_SET) != 0 || fread(ch, 4, 2, f) != 2)
            return err_set(err, "%s: GLB chunk %d cut short", name, chunk);
        if ((uint64_t)ch[0] > size - at - 8)
            return err_set(err, "%s: GLB chunk %d claims %u bytes, %llu are left", name, chunk, ch[0],
                           (unsigned long long)(size - at - 8));
        at += 8 + (uint64_t)ch[0];
    }
    return 0;
}

static int is_glb(const char *path)
{
    const char *e = extension(path);
    return strcmp(e, ".glb") == 0 || strcmp(e, ".GLB") == 0;
}

static int is_ply(const char *path)
{
    const char *e = extension(path);
    return strcmp(e, ".ply") == 0 || strcmp(e, ".PLY") == 0;
}

#define IMPORT_FLAGS (aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType | aiProcess_ValidateDataStructure)

static int import_scene(const struct aiScene *sc, const char *path, const char *model, int stl, Mesh *out,
                        ImportTexList *tl, ImportStats *st, Err *err);

/* glTF's KHR_texture_transform on a material's base colour texture: its
 * texture coordinates become offset + rotation(scale x uv), in glTF's
 * frame (v down; Assimp gives v up), the rotation (c s; -s c) as the
 * extension's sample model checks it (every arrow at its green mark).
 * Assimp 5.2.5 keeps the transform only as an aiUVTransform whose
 * translation is made for its own step (TransformUVCoords, which gets an
 * offset with a scale and every rotation wrong); the file's offset, scale
 * and rotation are taken back from it by the reader's formulas and
 * applied here.  In place: the scene is this process's own. */
static void import_uv_transforms(const struct aiScene *sc)
{
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        struct aiMesh *am = sc->mMeshes[i];
        struct aiUVTransform t;
        struct aiString mode;
        const struct aiMaterial *mt = am->mMaterialIndex < sc->mNumMaterials ? sc->mMaterials[am->mMaterialIndex] : NULL;
        if (!am->mTextureCoords[0] || !mt || !gltf_material(mt, &mode) ||
            aiGetMaterialUVTransform(mt, AI_MATKEY_UVTRANSFORM(aiTextureType_DIFFUSE, 0), &t) != aiReturn_SUCCESS)
            continue;
        const double sx = t.mScaling.x, sy = t.mScaling.y;
        double s, c;
        dmath_sincos(-(double)t.mRotation, &s, &c);
        const double tx = t.mTranslation.x, ty = t.mTranslation.y;
        const double ox = tx - 0.5 * sx * (-c + s + 1), oy = -(ty - 0.5 * sy * (s + c - 1) - 1 + sy);
        for (unsigned v = 0; v < am->mNumVertices; v++) {
            struct aiVector3D *uv = &am->mTextureCoords[0][v];
            const double u = sx * (double)uv->x, w = sy * (1 - (double)uv->y); /* scaled, in glTF's frame */
            uv->x = (ai_real)(ox + c * u + s * w);
            uv->y = (ai_real)(1 - (oy - s * u + c * w));
        }
    }
}

/* Blender's scenes are Z-up (its front view looks along +Y), as are
 * trueSpace's (.cob), and Assimp leaves them so: a standing figure lay on
 * its back and Suzanne showed the top of her head.  lanray is Y-up, as
 * glTF, OBJ and Assimp's other readers give it (3DS and COLLADA turned by
 * Assimp), so such a file's vertices and normals turn as Blender's own
 * glTF and OBJ exports turn them: (x, y, z) -> (x, z, -y), a rotation
 * (windings kept).  In place: the scene is this process's own (the
 * child's, isolation below).  ext: ".blend", or the memory reader's hint. */
static void import_upright(const struct aiScene *sc, const char *ext)
{
    static const char *const zup[] = {"blend", "cob"};
    int turn = 0;
    for (size_t i = 0; i < sizeof zup / sizeof *zup; i++)
        turn |= strcasecmp(ext + (ext[0] == '.'), zup[i]) == 0;
    if (!turn)
        return;
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        struct aiMesh *am = sc->mMeshes[i];
        for (unsigned v = 0; v < am->mNumVertices; v++) {
            struct aiVector3D *p = &am->mVertices[v], *n = am->mNormals ? &am->mNormals[v] : NULL;
            const ai_real y = p->y;
            p->y = p->z, p->z = -y;
            if (n) {
                const ai_real ny = n->y;
                n->y = n->z, n->z = -ny;
            }
        }
    }
}

/* In this process: what the child of import_read runs.  The materials'
 * textures are gathered into *tl, undecoded (import_texture.h). */
static int import_read_direct(const char *path, Mesh *out, ImportTexList *tl, ImportStats *st, Err *err)
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
    if (is_glb(path)) {
        FILE *f = fopen(path, "rb");
        if (!f)
            return err_set(err, "%s: cannot open", path);
        int seek = fseek(f, 0, SEEK_END);
        long size = seek == 0 ? ftell(f) : -1;
        int rc = size < 0 ? err_set(err, "%s: cannot read", path) : glb_check(f, (uint64_t)size, path, err);
        fclose(f);
        if (rc)
            return -1;
    }
    const struct aiScene *sc = aiImportFile(path, IMPORT_FLAGS);
    if (!sc)
        return assimp_failed(path, err);
    const char *e = extension(path);
    import_upright(sc, e);
    import_uv_transforms(sc);
    /* the scene stays: embedded images' bytes are Assimp's until sent
     * (the child ends after) */
    if (import_scene(sc, path, path, strcmp(e, ".stl") == 0 || strcmp(e, ".STL") == 0, out, tl, st, err))
        return -1;
    import_gltf_extensions(sc, path, NULL, 0, e[0] ? e + 1 : e, out, st);
    return 0;
}

static int import_read_memory_direct(const void *data, size_t len, const char *hint, const char *name, Mesh *out,
                                     ImportTexList *tl, ImportStats *st, Err *err)
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
    if (strcmp(hint, "glb") == 0) {
        FILE *f = len ? fmemopen((void *)(uintptr_t)data, len, "rb") : NULL;
        int rc = f ? glb_check(f, len, name, err) : err_set(err, "%s: not a GLB file (empty)", name);
        if (f)
            fclose(f);
        if (rc)
            return -1;
    }
    const struct aiScene *sc = aiImportFileFromMemory(data, (unsigned)len, IMPORT_FLAGS, hint);
    if (!sc)
        return assimp_failed(name, err);
    import_upright(sc, hint);
    import_uv_transforms(sc);
    if (import_scene(sc, name, NULL, strcmp(hint, "stl") == 0, out, tl, st, err))
        return -1;
    import_gltf_extensions(sc, NULL, data, len, hint, out, st);
    return 0;
}

/* A mesh's material index (0 where the file's is out of range). */
static uint32_t mesh_material(const struct aiScene *sc, const struct aiMesh *am)
{
    return am->mMaterialIndex < sc->mNumMaterials ? am->mMaterialIndex : 0;
}

/* Whether every mesh with vertex colours has a glTF material: their
 * colours then multiply its base colour. */
static int import_gltf_colours(const struct aiScene *sc)
{
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        struct aiString mode;
        const struct aiMesh *am = sc->mMeshes[i];
        if (am->mColors[0] && !gltf_material(sc->mMaterials[mesh_material(sc, am)], &mode))
            return 0;
    }
    return 1;
}

/* Whether the file has materials of its own: one that Assimp makes up for
 * a file without, unnamed (PLY, glTF) or "DefaultMaterial" (STL), is none,
 * as an OBJ without usemtl, so the scene's default applies. */
static int import_has_materials(const struct aiScene *sc)
{
    struct aiString name;
    if (sc->mNumMaterials != 1)
        return sc->mNumMaterials > 1;
    return aiGetMaterialString(sc->mMaterials[0], AI_MATKEY_NAME, &name) == aiReturn_SUCCESS && name.length &&
           strcmp(name.data, AI_DEFAULT_MATERIAL_NAME) != 0;
}

/* A texel of a BLEND material's alpha under this (half a code) is a hole. */
#define IMPORT_BLEND_CUTOFF (R(0.5) / R(255))

/* A glTF material of alphaMode MASK cuts holes where its alpha, the base
 * colour texture's times the base colour factor's (which Assimp gives as
 * the opacity), is under alphaCutoff (0.5 unless given; glTF 2.0 spec,
 * 3.9.4): the texture is its own mask, its texels cut under cutoff /
 * factor (above 1: every one; a factor of 0 cuts the whole surface).
 * Other materials are solid. */
static void import_cutout(const struct aiMaterial *am, Material *mt)
{
    struct aiString mode;
    if (mt->texture < 0 || !gltf_material(am, &mode))
        return;
    if (strcmp(mode.data, "BLEND") == 0) {
        if (!material_dielectric(mt)) {
            /* a BLEND whose factor is opaque: a see-through blend all the same,
             * its texels' alpha saying how much (import_optics made the others) */
            mt->ior = R(1);
            mt->kt = v3_splat(R(0));
            mt->coat = 0, mt->coat_roughness = 0; /* a see-through blend's reflection is its own (import_coat) */
        }
        if (mt->ior == R(1)) { /* not glass of its own (KHR_materials_transmission) */
            /* its texels blend by their alpha (glTF 2.0, 3.9.4); those of none
             * are holes, so that nothing is hit there at all */
            mt->mask = mt->texture;
            mt->cutoff = IMPORT_BLEND_CUTOFF;
            mt->mask_blend = 1;
        }
        return;
    }
    if (strcmp(mode.data, "MASK") != 0)
        return;
    ai_real cut = 0.5;
    aiGetMaterialFloatArray(am, "$mat.gltf.alphaCutoff", 0, 0, &cut, NULL);
    real factor = 1;
    import_number(am, AI_MATKEY_OPACITY, 0, 1, &factor);
    if (!(cut > 0)) /* a cutoff of 0 keeps every texel: solid */
        return;
    const real c = factor > R(0) ? (real)cut / factor : MATERIAL_CUTOFF_MAX;
    mt->mask = mt->texture;
    mt->cutoff = c < MATERIAL_CUTOFF_MAX ? c : MATERIAL_CUTOFF_MAX;
}

/* A material's normal map (glTF normalTexture, whose scale tilts it,
 * FBX's NormalMap): its index in *tl. */
static void import_normal_map(const struct aiScene *sc, const struct aiMaterial *am, const char *model,
                              ImportTexList *tl, Material *mt)
{
    const int32_t t = import_tex_find(sc, am, IMPORT_TEX_NORMALS, model, tl);
    ai_real scale = 1;
    aiGetMaterialFloatArray(am, AI_MATKEY_GLTF_TEXTURE_SCALE(aiTextureType_NORMALS, 0), &scale, NULL);
    if (t < 0 || !(scale > 0)) /* a scale of 0 leaves the normal as it is */
        return;
    mt->normal_map = t;
    mt->normal_scale = real_min((real)scale, MATERIAL_NORMAL_SCALE_MAX);
}

/* A glTF material's occlusion texture (occlusionTexture, its strength):
 * its index in *tl. */
static void import_occlusion(const struct aiScene *sc, const struct aiMaterial *am, const char *model,
                             ImportTexList *tl, Material *mt)
{
    const int32_t t = import_tex_find(sc, am, IMPORT_TEX_OCCLUSION, model, tl);
    ai_real strength = 1;
    aiGetMaterialFloatArray(am, AI_MATKEY_GLTF_TEXTURE_STRENGTH(aiTextureType_LIGHTMAP, 0), &strength, NULL);
    if (t < 0 || !(strength > 0)) /* a strength of 0 occludes nothing */
        return;
    mt->ao_map = t;
    mt->ao_strength = real_min((real)strength, R(1));
}

/* Every material of the file into out, in the file's order, with its
 * texture (an index into *tl) where the model has texture coordinates. */
static int import_materials(const struct aiScene *sc, const char *model, int has_t, Mesh *out, ImportTexList *tl,
                            ImportStats *st, Err *err)
{
    int rc = 0;
    for (unsigned i = 0; rc == 0 && i < sc->mNumMaterials; i++) {
        int optics;
        MetalFactors mf;
        Material mt = import_material(sc->mMaterials[i], &optics, &mf);
        st->optics += (unsigned long)optics;
        mt.texture = has_t ? import_tex_find(sc, sc->mMaterials[i], IMPORT_TEX_COLOUR, model, tl) : -1;
        import_cutout(sc->mMaterials[i], &mt);
        if (has_t)
            import_normal_map(sc, sc->mMaterials[i], model, tl, &mt);
        /* an emission texture multiplies the emissive factor, which glTF's
         * exporters set to 1 where a texture glows (glTF 2.0, 3.9.3) */
        const int32_t glow = has_t && material_emits(&mt)
                                 ? import_tex_find(sc, sc->mMaterials[i], IMPORT_TEX_EMISSION, model, tl) : -1;
        if (glow >= 0)
            mt.emit_map = glow, mt.emit_mapped = 1;
        int32_t metal = has_t && mf.mapped
                            ? import_tex_find(sc, sc->mMaterials[i], IMPORT_TEX_METAL, model, tl) : -1;
        /* glTF's metal reflects its base colour, texel by texel: a metal by
         * its factors alone whose base colour is a texture takes a uniform
         * metal-roughness texture (import_tex_white), so that its mirror
         * is tinted by the texture where its factors tinted it with the
         * base colour factor alone (a gold texture's mirror was white) */
        if (metal < 0 && mt.texture >= 0 && !mf.mapped && v3_max_comp(mt.kr) > R(0)) {
            metal = import_tex_white(tl);
            mf.mapped = 1;
        }
        if (metal >= 0) {
            import_metal_as(&mf, &mt);
            import_optics(sc->mMaterials[i], mf.base, &mf, &mt);
            import_coat(sc->mMaterials[i], &mf, &mt);
            mt.metal_map = metal, mt.metal_mapped = 1;
        }
        if (has_t)
            import_occlusion(sc, sc->mMaterials[i], model, tl, &mt);
        rc = mesh_add_material(out, mt, err);
    }
    return rc;
}

/* The triangles of an imported scene into *out (stats counted); each
 * material's texture is an index into *tl.  `model`: the file's path, where
 * textures named by a relative path are looked for (NULL: none). */
static int import_scene(const struct aiScene *sc, const char *path, const char *model, int stl, Mesh *out,
                        ImportTexList *tl, ImportStats *st, Err *err)
{
    int has_n = 0, has_t = 0, has_c = 0;
    unsigned long faces = 0;
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        const struct aiMesh *am = sc->mMeshes[i];
        if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
            continue;
        has_n |= am->mNormals != NULL && !stl;
        has_t |= am->mTextureCoords[0] != NULL;
        has_c |= am->mColors[0] != NULL;
        st->coloured += am->mColors[0] ? am->mNumVertices : 0;
        faces += am->mNumFaces;
    }
    int rc = 0;
    if (faces > IMPORT_MAX_TRIANGLES)
        rc = err_set(err, "%s: %lu triangles exceed the limit of %u", path, faces, IMPORT_MAX_TRIANGLES);
    const int has_m = import_has_materials(sc);
    /* vertex colours (scanners write them in PLY) where the model has no
     * material colour, as the OBJ reader keeps them; and in a glTF, whose
     * COLOR_0 multiplies its material's base colour (the glTF spec), with
     * materials too */
    const int gltf_colours = has_c && has_m && import_gltf_colours(sc);
    if (has_c && has_m && !gltf_colours) {
        st->colours_ignored = 1;
        has_c = 0;
    }
    if (rc == 0)
        rc = mesh_init(out, (has_n ? MESH_NORMALS : 0u) | (has_t ? MESH_UVS : 0u) | (has_m ? MESH_MATERIALS : 0u) |
                                (has_c ? MESH_COLOURS : 0u),
                       err);
    if (rc == 0 && has_m)
        rc = import_materials(sc, model, has_t, out, tl, st, err);
    const vec3 default_kd = material_default().kd;
    for (unsigned i = 0; rc == 0 && i < sc->mNumMeshes; i++) {
        const struct aiMesh *am = sc->mMeshes[i];
        st->meshes++;
        st->vertices += am->mNumVertices;
        /* a glTF's colours multiply its material's diffuse colour; a mesh
         * without colours beside ones with takes that, or the default */
        const vec3 kd = gltf_colours ? out->materials[mesh_material(sc, am)].kd : default_kd;
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
            vec3 p[3], n[3], col[3];
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
                if (has_c) {
                    const struct aiColor4D *c = am->mColors[0];
                    col[k] = c ? v3(c[v].r, c[v].g, c[v].b) : kd;
                    if (c && gltf_colours)
                        col[k] = v3_mul(col[k], kd);
                    if (!v3_is_finite(col[k]) || col[k].x < 0 || col[k].y < 0 || col[k].z < 0)
                        bad = 2;
                }
            }
            if (bad == 2) {
                rc = err_set(err, "%s: mesh %u face %u: a vertex colour that is negative or not a finite number", path, i, f);
                break;
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
                vec3 fn = v3_norm_any(v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0])));
                for (int k = 0; k < 3; k++) {
                    n[k] = v3_norm(n[k]);
                    if (!(v3_dot(n[k], n[k]) > R(0.5)))
                        n[k] = fn;
                }
            }
            uint32_t mat = has_m ? mesh_material(sc, am) : 0;
            rc = mesh_add(out, p, has_n ? n : NULL, has_t ? uv : NULL, has_c ? col : NULL, mat, err);
        }
    }
    if (rc) {
        mesh_free(out);
        return -1;
    }
    st->triangles = out->tri_count;
    return 0;
}

/* ---- isolation: Assimp runs in a child process ----
 *
 * Assimp 5.2.5 crashes on some malformed files (fuzz_import found a SIGBUS
 * in its post-processing of a mutated PLY): a crash in a library we do not
 * own must not take obj2tmd, lanray-render or a server down.  The child
 * imports and sends the Mesh back through a pipe; the parent reads it with
 * every size checked.  A child that dies, or sends less than a whole
 * answer, is an error naming the file. */
#define IMPORT_MAX_REPLY ((size_t)4 << 30)

static void send_mesh(int fd, int rc, const Mesh *m, const ImportTexList *tl, const ImportStats *st, const Err *err)
{
    Sink o = {0};
    sink_u32(&o, (uint32_t)(rc == 0));
    if (rc) {
        sink_put(&o, err->msg, sizeof err->msg);
    } else {
        sink_put(&o, st, sizeof *st);
        uint32_t head[5] = {m->tri_count, mesh_attrs(m), m->material_count, 0, 0};
        sink_put(&o, head, sizeof head);
        sink_put(&o, m->pos, (size_t)m->tri_count * 3 * sizeof *m->pos);
        if (m->nrm)
            sink_put(&o, m->nrm, (size_t)m->tri_count * 3 * sizeof *m->nrm);
        if (m->uv)
            sink_put(&o, m->uv, (size_t)m->tri_count * 6 * sizeof *m->uv);
        if (m->mat)
            sink_put(&o, m->mat, (size_t)m->tri_count * sizeof *m->mat);
        if (m->col)
            sink_put(&o, m->col, (size_t)m->tri_count * 3 * sizeof *m->col);
        sink_put(&o, m->materials, (size_t)m->material_count * sizeof *m->materials);
        import_tex_send(&o, tl);
    }
    const uint8_t *p = o.data;
    size_t left = o.failed ? 0 : o.len;
    while (left) {
        ssize_t n = write(fd, p, left);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        p += n, left -= (size_t)n;
    }
    sink_free(&o);
}

/* A material's map (*idx, an entry of the child's list) as the mesh's
 * texture (map: -1 where it could not be read): whether the map is used
 * and stands; else *idx is 0, as a material without the map has it. */
static int map_stands(int32_t *idx, int used, const int32_t *map)
{
    *idx = used ? map[*idx] : 0;
    if (*idx >= 0)
        return used;
    *idx = 0;
    return 0;
}

/* A glTF's mask (MASK or BLEND: import.c's are glTF's) whose texture has
 * no alpha: its texels are opaque (glTF 2.0, 3.9.4), not as grey as their
 * colour (an MTL map_d's reading): a BLEND blends by its factor alone, a
 * MASK cuts everywhere where its factor is under the cutoff (cutoff > 1),
 * else nowhere. */
static void opaque_mask(Material *mt)
{
    mt->mask_blend = 0;
    if (mt->cutoff > R(1))
        return;
    mt->cutoff = 0;
    mt->mask = 0;
}

static int receive_mesh(const uint8_t *data, size_t len, const char *name, const ObjOptions *opt, Mesh *out,
                        ImportStats *st, Err *err)
{
    Cursor c = cursor_make(data, len);
    uint32_t ok = cursor_u32(&c);
    if (c.failed)
        return err_set(err, "%s: the importer sent nothing", name);
    if (!ok) {
        Err child;
        if (cursor_get(&c, child.msg, sizeof child.msg))
            return err_set(err, "%s: the importer failed", name);
        child.msg[sizeof child.msg - 1] = 0;
        return err_set(err, "%s", child.msg);
    }
    uint32_t head[5];
    if (cursor_get(&c, st, sizeof *st) || cursor_get(&c, head, sizeof head))
        return err_set(err, "%s: the importer's answer is cut short", name);
    uint32_t n = head[0], attrs = head[1], nmat = head[2];
    int has_n = attrs & MESH_NORMALS, has_t = attrs & MESH_UVS, has_m = attrs & MESH_MATERIALS,
        has_c = attrs & MESH_COLOURS;
    if (n > IMPORT_MAX_TRIANGLES || nmat > 65536 || (has_m && !nmat) || attrs > 15 || head[3] || head[4])
        return err_set(err, "%s: the importer's answer is implausible", name);
    size_t need = (size_t)n * (3 * sizeof(vec3) + (has_n ? 3 * sizeof(vec3) : 0) + (has_t ? 6 * sizeof(real) : 0) +
                               (has_m ? sizeof(uint32_t) : 0) + (has_c ? 3 * sizeof(vec3) : 0)) +
                  (size_t)nmat * sizeof(Material);
    if (need > c.left)
        return err_set(err, "%s: the importer's answer is cut short", name);
    if (mesh_init(out, attrs, err))
        return -1;
    /* the textures after the materials: decoded first, so that the
     * materials can name them */
    Cursor tc = cursor_make(c.p + need, c.left - need);
    int32_t *map = malloc(IMPORT_TEX_MAX * sizeof *map);
    uint32_t ntex = 0;
    if (!map || import_tex_receive(&tc, name, opt, &st->warnings, &st->missing_textures, out, map, &ntex, err) ||
        (tc.left != 0 && err_set(err, "%s: the importer's answer has %zu bytes too many", name, tc.left))) {
        if (!map)
            err_set(err, "%s: out of memory", name);
        free(map);
        mesh_free(out);
        return -1;
    }
    st->textures = out->texture_count;
    /* triangles one by one through mesh_add, which owns the arrays' growth */
    const uint8_t *pos = c.p, *nrm = pos + (size_t)n * 3 * sizeof(vec3);
    const uint8_t *uv = nrm + (has_n ? (size_t)n * 3 * sizeof(vec3) : 0);
    const uint8_t *mat = uv + (has_t ? (size_t)n * 6 * sizeof(real) : 0);
    const uint8_t *col = mat + (has_m ? (size_t)n * sizeof(uint32_t) : 0);
    const uint8_t *mats = col + (has_c ? (size_t)n * 3 * sizeof(vec3) : 0);
    for (uint32_t i = 0; i < nmat; i++) {
        Material mt;
        memcpy(&mt, mats + (size_t)i * sizeof mt, sizeof mt);
        if (!material_textures_in(&mt, (int32_t)ntex)) {
            free(map);
            mesh_free(out);
            return err_set(err, "%s: the importer's answer is implausible (material %u's texture)", name, i);
        }
        mt.texture = mt.texture < 0 ? -1 : map[mt.texture];
        /* a map that could not be read does nothing: a mask cuts nothing, a
         * normal map tilts nothing, an emission's factor glows alone, a
         * metal-roughness texture leaves the material diffuse (as before),
         * an occlusion texture occludes nothing */
        if (!map_stands(&mt.mask, material_cuts(&mt), map))
            mt.cutoff = 0, mt.mask_blend = 0;
        if (material_cuts(&mt) && !out->textures[mt.mask]->alpha)
            opaque_mask(&mt);
        if (!map_stands(&mt.normal_map, material_bumps(&mt), map))
            mt.normal_scale = 0;
        if (!map_stands(&mt.emit_map, material_emit_mapped(&mt), map))
            mt.emit_mapped = 0;
        if (material_metal_mapped(&mt) && !map_stands(&mt.metal_map, 1, map))
            mt = material_unmetal(mt);
        if (!map_stands(&mt.ao_map, material_occludes(&mt), map))
            mt.ao_strength = 0;
        if (mesh_add_material(out, mt, err)) {
            free(map);
            mesh_free(out);
            return -1;
        }
    }
    free(map);
    for (uint32_t i = 0; i < n; i++) {
        vec3 p[3], q[3], k[3];
        real u[6];
        uint32_t id = 0;
        memcpy(p, pos + (size_t)i * sizeof p, sizeof p);
        if (has_n)
            memcpy(q, nrm + (size_t)i * sizeof q, sizeof q);
        if (has_t)
            memcpy(u, uv + (size_t)i * sizeof u, sizeof u);
        if (has_m)
            memcpy(&id, mat + (size_t)i * sizeof id, sizeof id);
        if (has_c)
            memcpy(k, col + (size_t)i * sizeof k, sizeof k);
        if (id >= (nmat ? nmat : 1)) {
            mesh_free(out);
            return err_set(err, "%s: the importer's answer is implausible", name);
        }
        if (mesh_add(out, p, has_n ? q : NULL, has_t ? u : NULL, has_c ? k : NULL, id, err)) {
            mesh_free(out);
            return -1;
        }
    }
    return 0;
}

typedef struct {
    const char *path;
    const void *data;
    size_t len;
    const char *hint;
} Job;

/* Sanitizer builds let a death callback run when they stop a process
 * (libFuzzer's writes a crash file): the child's death is the parent's
 * error, not a finding of its own.  Weak: absent in ordinary builds. */
void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

static void child_die(void) { _exit(3); }

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define IMPORT_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define IMPORT_SANITIZED 1
#endif
#endif

/* The importer's address space: 4 GiB, or 256 bytes a byte of the file
 * where that is more.  Assimp 5.2.5 believes what a file says: a 2 KB
 * COLLADA file whose triangle list held a stray '=' made it take 12.6 GB
 * and 45 s (fuzz_import, 2026-11-29); capped, its allocation fails and
 * the import is an error naming the file.  Not under a sanitizer, whose
 * shadow memory is a reservation of terabytes already. */
#define IMPORT_MEMORY_MIN ((uint64_t)4 << 30)
#define IMPORT_MEMORY_PER_BYTE 256u

static void child_memory_cap(const Job *job)
{
#ifndef IMPORT_SANITIZED
    uint64_t size = job->len;
    struct stat sb;
    if (job->path && stat(job->path, &sb) == 0)
        size = (uint64_t)sb.st_size;
    const uint64_t cap = size > IMPORT_MEMORY_MIN / IMPORT_MEMORY_PER_BYTE ? size * IMPORT_MEMORY_PER_BYTE
                                                                            : IMPORT_MEMORY_MIN;
    const struct rlimit rl = {.rlim_cur = (rlim_t)cap, .rlim_max = (rlim_t)cap};
    setrlimit(RLIMIT_AS, &rl); /* where it cannot be set, the import runs uncapped, as before */
#else
    (void)job;
#endif
}

/* The child dies of a crash by the default action, whatever handlers its
 * parent had installed (a fuzzer's, a sanitizer's), and within its memory
 * cap. */
static void child_defaults(const Job *job)
{
    static const int fatal[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT};
    for (size_t i = 0; i < sizeof fatal / sizeof *fatal; i++)
        signal(fatal[i], SIG_DFL);
    if (__sanitizer_set_death_callback)
        __sanitizer_set_death_callback(child_die);
    child_memory_cap(job);
}

static int isolated(const Job *job, const char *name, const ObjOptions *opt, Mesh *out, ImportStats *st, Err *err)
{
    memset(out, 0, sizeof *out);
    memset(st, 0, sizeof *st);
    int fds[2];
    if (pipe(fds))
        return err_set(err, "%s: cannot start the importer: %s", name, strerror(errno));
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]), close(fds[1]);
        return err_set(err, "%s: cannot start the importer: %s", name, strerror(errno));
    }
    if (pid == 0) {
        close(fds[0]);
        child_defaults(job);
        Mesh m;
        ImportStats cs;
        ImportTexList tl = {0};
        Err cerr = {{0}};
        int rc = job->path ? import_read_direct(job->path, &m, &tl, &cs, &cerr)
                           : import_read_memory_direct(job->data, job->len, job->hint, name, &m, &tl, &cs, &cerr);
        send_mesh(fds[1], rc, &m, &tl, &cs, &cerr);
        _exit(0);
    }
    close(fds[1]);
    uint8_t *buf = NULL;
    size_t len = 0, cap = 0;
    int rc = 0;
    for (;;) {
        if (len == cap) {
            size_t ncap = cap ? 2 * cap : 65536;
            uint8_t *nb = ncap <= IMPORT_MAX_REPLY ? realloc(buf, ncap) : NULL;
            if (!nb) {
                rc = err_set(err, "%s: the importer's answer is too large", name);
                kill(pid, SIGKILL);
                break;
            }
            buf = nb, cap = ncap;
        }
        ssize_t n = read(fds[0], buf + len, cap - len);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        len += (size_t)n;
    }
    close(fds[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (rc == 0 && WIFSIGNALED(status))
        rc = err_set(err, "%s: the importer (Assimp) crashed on this file (signal %d): it is malformed", name,
                     WTERMSIG(status));
    else if (rc == 0 && (!WIFEXITED(status) || WEXITSTATUS(status) != 0))
        rc = err_set(err, "%s: the importer (Assimp) failed on this file (exit %d): it is malformed", name,
                     WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    if (rc == 0)
        rc = receive_mesh(buf, len, name, opt, out, st, err);
    free(buf);
    return rc;
}

/* The warning for n glTF materials whose extension's value (`what`) was
 * not applied: twins of theirs differ in it alone (import_extensions.h). */
static int twins_warning(const ObjOptions *opt, const char *name, unsigned long n, const char *what, ImportStats *st,
                         Err *err)
{
    char msg[4200];
    if (!n)
        return 0;
    snprintf(msg, sizeof msg,
             "%s: %s of %lu material%s not applied: materials of one name, emissive and base colour differ in it only",
             name, what, n, n == 1 ? "" : "s");
    return obj_warning(opt, &st->warnings, err, msg);
}

/* The parent's own warnings about what the child reported. */
static int import_warnings(const ObjOptions *opt, const char *name, Mesh *out, ImportStats *st, Err *err)
{
    char msg[4200];
    snprintf(msg, sizeof msg, "%s: vertex colours ignored: the model's materials give its colours", name);
    if ((st->colours_ignored && obj_warning(opt, &st->warnings, err, msg)) ||
        twins_warning(opt, name, st->strength_unknown, "emission strength (KHR_materials_emissive_strength)", st, err) ||
        twins_warning(opt, name, st->specular_unknown, "specular (KHR_materials_specular)", st, err)) {
        mesh_free(out);
        return -1;
    }
    return 0;
}

int import_read(const char *path, const ObjOptions *opt, Mesh *out, ImportStats *st, Err *err)
{
    ImportStats local;
    Job job = {path, NULL, 0, NULL};
    if (!st)
        st = &local;
    if (!import_knows(path)) {
        memset(out, 0, sizeof *out);
        return err_set(err, "%s: not a format the importer reads (PLY, STL, glTF, ...)", path);
    }
    if (isolated(&job, path, opt, out, st, err))
        return -1;
    /* opt->smooth: vertex normals for a file that has none (STL, a PLY
     * without them), sharp edges kept (IMPORT_CREASE_DEG) */
    if (opt && opt->smooth && !out->nrm) {
        if (mesh_smooth(out, IMPORT_CREASE_DEG, err)) {
            mesh_free(out);
            return err_prefix(err, "%s", path);
        }
        st->smoothed = out->tri_count;
    }
    return import_warnings(opt, path, out, st, err);
}

int import_read_memory(const void *data, size_t len, const char *hint, const char *name, const ObjOptions *opt,
                       Mesh *out, ImportStats *st, Err *err)
{
    ImportStats local;
    Job job = {NULL, data, len, hint};
    if (!st)
        st = &local;
    if (isolated(&job, name, opt, out, st, err))
        return -1;
    return import_warnings(opt, name, out, st, err);
}

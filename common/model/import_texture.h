/* import_texture.h - the textures an imported model's materials name, on
 * their way from the importer's child process (where Assimp runs) to the
 * parent (import.c's isolation).
 *
 * The child only finds each material's diffuse (glTF: base colour)
 * texture, its normal map and its emission texture and collects their
 * bytes, undecoded: an
 * image embedded in the file (a glTF's bufferView or data URI, an FBX's),
 * or the file a relative path names beside the model (file_find_near,
 * as the OBJ reader finds its textures); a texture it cannot find travels as missing, with why.  The
 * parent decodes each with lanray's own readers (texture_read_memory: the
 * same hardened code as every texture file), so that a malformed image is
 * an error of the parent's, named, never a crash inside Assimp's process;
 * a texture that cannot be read is a warning naming it (an error with
 * --strict) and leaves its material untextured. */
#ifndef LANRAY_IMPORT_TEXTURE_H
#define LANRAY_IMPORT_TEXTURE_H

#include <stdint.h>

#include "base/cursor.h"
#include "model/mesh.h"
#include "model/obj.h"

struct aiScene;
struct aiMaterial;

typedef enum { IMPORT_TEX_FILE = 0, IMPORT_TEX_BGRA = 1, IMPORT_TEX_MISSING = 2 } ImportTexKind;

#define IMPORT_TEX_CLOSEST 1u /* magnified, texels stay squares (glTF magFilter NEAREST) */
#define IMPORT_TEX_WRAP_U 1   /* bits 1-2: u's TextureWrap (glTF wrapS) */
#define IMPORT_TEX_WRAP_V 3   /* bits 3-4: v's (wrapT) */
#define IMPORT_TEX_NAME 512

typedef struct {
    uint32_t kind; /* ImportTexKind */
    uint32_t w, h; /* IMPORT_TEX_BGRA: the texels' size */
    uint32_t flags;
    char key[IMPORT_TEX_NAME];  /* what the material says ("*0", "textures/duck.png"): one entry a key */
    char name[IMPORT_TEX_NAME]; /* for messages: the file found, or "embedded image N (png)"; missing: why */
    const uint8_t *bytes;       /* the image file's bytes, or w x h BGRA texels; none when missing */
    size_t len;
    uint8_t *own; /* what to free: bytes read from a file */
} ImportTex;

typedef struct {
    ImportTex *t;
    uint32_t n, cap;
} ImportTexList;

/* Which of a material's textures: its colour's (diffuse, base colour),
 * its normal map, its emission's, its metal-roughness texture, or its
 * occlusion texture. */
typedef enum {
    IMPORT_TEX_COLOUR = 0,
    IMPORT_TEX_NORMALS = 1,
    IMPORT_TEX_EMISSION = 2,
    IMPORT_TEX_METAL = 3,
    IMPORT_TEX_OCCLUSION = 4
} ImportTexRole;

/* The child: material am's texture of that role, added to l once per key;
 * its index in l, or -1 when the material has none (or a normal map or
 * emission texture on a second set of texture coordinates).  `model` is the model file's path (NULL for
 * a model in memory: relative paths are missing). */
int32_t import_tex_find(const struct aiScene *sc, const struct aiMaterial *am, ImportTexRole role, const char *model,
                        ImportTexList *l);
/* The child: a texture of one white texel, added to l once; its index, or
 * -1.  The metal-roughness texture of a metal whose base colour is a
 * texture and whose metal share is its factors' alone: through it a hit
 * takes the texel's colour for its mirror's tint (trace.c surface_metal),
 * as a mapped metal's does, where the factors alone tint every texel's
 * mirror with the base colour factor. */
int32_t import_tex_white(ImportTexList *l);
void import_tex_free(ImportTexList *l);
/* The child: the list into the answer it sends. */
void import_tex_send(Sink *o, const ImportTexList *l);

/* The parent: reads the list from the answer (every size checked),
 * decodes each texture into out (mesh_add_texture) and writes in map[i]
 * the mesh's texture of entry i, or -1 where it could not be read (a
 * warning through opt).  *count: the entries (at most 65536); map has room
 * for that many. */
int import_tex_receive(Cursor *c, const char *name, const ObjOptions *opt, unsigned long *warnings,
                       unsigned long *missing, Mesh *out, int32_t *map, uint32_t *count, Err *err);
#define IMPORT_TEX_MAX 65536u

#endif

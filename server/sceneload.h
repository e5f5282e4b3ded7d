/* sceneload.h - a scene read on a thread of its own.
 *
 * Reading a scene again (an edit) or a file dropped on the window means
 * parsing its models and building their trees: a second or more for a
 * model of a million triangles.  Read in the server's loop, that second
 * was a frozen window and a farm with nothing to do; read here, the scene
 * shown goes on being served and drawn, and the new one is handed over
 * once it is whole.  One read a SceneLoad; the function given does the
 * reading and must touch nothing the loop uses meanwhile. */
#ifndef LANRAY_SCENELOAD_H
#define LANRAY_SCENELOAD_H

#include "base/err.h"
#include "net/asset.h"
#include "scene/scene.h"

/* What a read gives: the path read (the caller's to free, with the scene
 * and its assets once sceneload_finish gave them), the scene (NULL on
 * failure, err saying why), its assets as the clients are sent them
 * (asset_make_scene's), and the settings it asked for itself, before the
 * command line's went over them. */
typedef struct {
    char *path;
    Scene *scene;
    Asset *assets;
    uint32_t nassets;
    RenderSettings asked;
    Err err;
} SceneRead;

/* Reads the scene of path into r's scene, asked and err (on the loader's
 * thread). */
typedef void (*SceneReadFn)(const void *ctx, const char *path, SceneRead *r);

typedef struct SceneLoad SceneLoad;

/* Starts reading path (copied) with fn(ctx, ...): ctx must stay valid and
 * unchanged until sceneload_finish.  NULL with err set when no thread
 * could be started. */
SceneLoad *sceneload_start(const char *path, SceneReadFn fn, const void *ctx, Err *err);
/* Whether the read is over (never blocks). */
int sceneload_done(SceneLoad *l);
/* The path being read. */
const char *sceneload_path(const SceneLoad *l);
/* Waits for the read, frees l and gives what it read (the path and the
 * scene are the caller's). */
SceneRead sceneload_finish(SceneLoad *l);

#endif

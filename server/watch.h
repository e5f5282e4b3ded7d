/* watch.h - the files a scene was read from, watched for edits (inotify).
 *
 * The directories of a scene's sources (Scene.sources: the scene file, its
 * models' and textures' files) are watched, not the files themselves, so
 * that an editor that writes a new file and renames it over the old one is
 * seen too.  An event for a file of another name in those directories is
 * ignored.  (The files a model reads itself, an OBJ's MTL and the MTL's
 * textures, are not among the sources: touch the scene or the model file
 * after editing them.) */
#ifndef LANRAY_WATCH_H
#define LANRAY_WATCH_H

#include "base/err.h"
#include "scene/scene.h"

typedef struct Watch Watch;

/* NULL with err set where inotify is not there or a directory cannot be watched. */
Watch *watch_open(const Scene *s, Err *err);
void watch_close(Watch *w);
/* Reads the events that came (never blocks): 1 when one named a source. */
int watch_changed(Watch *w);

#endif

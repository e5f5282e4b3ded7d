/* livescene.h - the scene shown replaced while the server runs: read
 * again when it or a file it names is edited, or a scene file or model
 * dropped on the window opened in its place.  Each is read on a thread
 * (sceneload.h), while the scene shown goes on being served, and handed
 * to the server for the frame after the read; an error keeps the scene
 * shown and says why, in the log and the window's title. */
#ifndef LANRAY_LIVESCENE_H
#define LANRAY_LIVESCENE_H

#include "app.h"
#include "args.h"

/* Once a turn of the loop: the scene handed over taken (the old one
 * freed), a read that is over handed over, an edit that came 0.15 s ago
 * (an editor's writes are over by then) read. */
void livescene_step(App *app, const Args *a);
/* A file dropped on the window: read, then shown in place of the scene
 * (its camera, its framing), its files followed from then on.  A newer
 * drop or edit while one is read is read after it, the older dropped. */
void livescene_drop(App *app, const Args *a, const char *path);
/* The file name of a dropped file being opened, for the title, or NULL. */
const char *livescene_opening(const App *app);
/* The window's still quality and frame-rate target for scene s, where
 * the command line did not say them (at the start, and for a dropped
 * scene): a path-traced view converges once it stops to 1024 samples a
 * pixel (its still frames add up) and moves at 10 frames a second, fewer
 * pixels while it moves, as Cycles' viewport does; a Whitted view is not
 * refined and has no target.  (A path-traced scene dropped on a Whitted
 * window without them stayed at one sample a pixel, its noise never
 * going.) */
void livescene_defaults(App *app, const Args *a, const Scene *s);
/* Waits for a read under way and drops it (the server's end). */
void livescene_close(App *app);

#endif

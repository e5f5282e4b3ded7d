/* livescene.c - see livescene.h. */
#include "livescene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/cli.h"
#include "base/fileio.h"
#include "base/log.h"
#include "base/timer.h"

/* What an edited scene asks of the frames (rs: its settings before the
 * command line's).  A new size: a window whose frames follow its size
 * takes it (the frames follow); headless, or at --fixed-size, the frames
 * stay (the frames written are one size).  Denoise,
 * which the server cannot take while it runs (the pixels' size follows
 * it).  Said, not dropped without a word. */
static void edit_frame_settings(App *app, const Args *a, const RenderSettings *rs)
{
    const int w = !a->width_given && rs->width ? rs->width : app->asked_w;
    const int h = !a->height_given && rs->height ? rs->height : app->asked_h;
    if (w != app->asked_w || h != app->asked_h) {
        app->asked_w = w, app->asked_h = h;
        if (app->display && app->win.follow) {
            display_set_size(app->display, w, h);
            log_line(a->cfg.quiet, "lanray-server", "%s asks for %dx%d frames: the window takes that size",
                     app->scene_path, w, h);
        } else {
            fprintf(stderr, "lanray-server: %s asks for %dx%d frames; they stay %dx%d until the server is started again\n",
                    app->scene_path, w, h, app->width, app->height);
        }
    }
    if (!a->denoise_given && rs->denoise != a->denoise)
        fprintf(stderr, "lanray-server: %s asks for denoise %s; the frames stay %s until the server is started again\n",
                app->scene_path, rs->denoise ? "on" : "off", a->denoise ? "denoised" : "raw");
}

/* A scene that could not be read (an edit, a file dropped on the window):
 * the one shown stays, and the log and the title say why. */
static void keep_scene(App *app, const Err *err, const char *why)
{
    fprintf(stderr, "lanray-server: %s (%s)\n", err->msg, why);
    snprintf(app->edit_error, sizeof app->edit_error, "%s", err->msg);
    app->last_title = 0;
}

/* A scene read (next, rs its settings before the command line's) handed
 * to the server for the next frame, its files watched from now on. */
static void hand_over(App *app, const Args *a, SceneRead *r)
{
    Scene *next = r->scene;
    if (app->display)
        window_knobs_apply(&app->win, &next->settings);
    edit_frame_settings(app, a, &r->asked);
    scene_destroy(app->pending);
    app->pending = next;
    server_set_scene(app->server, next, r->assets, r->nassets);
    r->assets = NULL, r->nassets = 0;
    app->edit_error[0] = 0;
    Err err;
    Watch *w = watch_open(next, &err); /* its files from now on */
    if (w) {
        watch_close(app->watch);
        app->watch = w;
    }
}

/* The scene handed over, once the server took it: the old one is free,
 * and a dropped file's name is the title's. */
static void adopt_taken(App *app)
{
    if (app->pending && server_scene(app->server) == app->pending) {
        scene_destroy(app->scene);
        app->scene = app->pending;
        app->pending = NULL;
        if (app->opening_name) {
            snprintf(app->shown_name, sizeof app->shown_name, "%s", app->opening_name);
            app->name = app->shown_name;
            app->opening_name = NULL;
            app->last_title = 0;
        }
    }
}

/* On the loader's thread: the scene of path, and the command line's
 * settings over its own.  Reads only a (fixed while the server runs). */
static void read_scene(const void *ctx, const char *path, SceneRead *r)
{
    const Args *a = ctx;
    if (cli_open_scene(path, &a->bvh, a->force_bvh, args_smooth_for(a, path), &r->scene, &r->err)) {
        r->scene = NULL;
        return;
    }
    r->asked = r->scene->settings;
    /* its assets too: the clients are sent them as soon as it is handed
     * over (server/ahead.c) */
    if (args_apply(r->scene, a, path, &r->err) || asset_make_scene(r->scene, &r->assets, &r->nassets, &r->err)) {
        scene_destroy(r->scene);
        r->scene = NULL;
    }
}

/* A read's scene and assets, not handed over. */
static void read_drop(SceneRead *r)
{
    scene_destroy(r->scene);
    assets_free(r->assets, r->nassets);
    free(r->path);
}

static const char *stays(int drop) { return drop ? "the scene shown stays" : "the last good scene stays"; }

/* Reads path (a file dropped, or the scene shown, edited) or, while a read
 * is under way, queues it to be read after (that one's scene dropped).
 * An edit of the scene shown is moot while a dropped file is to replace
 * it. */
static void request(App *app, const Args *a, const char *path, int drop)
{
    Err err;
    if (app->loading) {
        if (!drop && (app->loading_drop || (app->queued && app->queued_drop)))
            return;
        char *copy = strdup(path);
        if (!copy) {
            err_set(&err, "%s: out of memory", path);
            keep_scene(app, &err, stays(drop));
            return;
        }
        free(app->queued);
        app->queued = copy;
        app->queued_drop = drop;
        return;
    }
    app->loading = sceneload_start(path, read_scene, a, &err);
    if (!app->loading) {
        keep_scene(app, &err, stays(drop));
        return;
    }
    app->loading_drop = drop;
    app->loading_t = timer_now();
    app->loading_frames = app->frames_done;
    app->last_title = 0; /* "opening NAME ..." */
}

/* A dropped file read: it is the scene shown now, its name in the title. */
static void adopt_dropped(App *app, const Args *a, char *path, Scene *next)
{
    /* the title names the scene shown until the server takes this one
     * (its models on their way to the clients: server/ahead.c) */
    if (app->name && app->name != app->shown_name) {
        snprintf(app->shown_name, sizeof app->shown_name, "%s", app->name);
        app->name = app->shown_name;
    }
    free(app->dropped);
    app->dropped = path;
    app->scene_path = path;
    app->opening_name = file_basename(path);
    window_new_scene(&app->win, next);
    livescene_defaults(app, a, next);
}

/* A read over: handed to the server, or, where a newer one waits, dropped
 * for it. */
static void take_read(App *app, const Args *a)
{
    if (!app->loading || !sceneload_done(app->loading))
        return;
    const int drop = app->loading_drop;
    SceneRead r = sceneload_finish(app->loading);
    app->loading = NULL;
    app->last_title = 0;
    if (app->queued) {
        read_drop(&r);
        char *next = app->queued;
        app->queued = NULL;
        request(app, a, next, app->queued_drop);
        free(next);
        return;
    }
    if (!r.scene) {
        keep_scene(app, &r.err, stays(drop));
        free(r.path);
        return;
    }
    hand_over(app, a, &r);
    /* the frames the farm went on with while it was read (none where the
     * window was still: no frame is rendered then) */
    const uint32_t meanwhile = app->frames_done - app->loading_frames;
    char frames[48] = "";
    if (meanwhile)
        snprintf(frames, sizeof frames, " (%u frames shown meanwhile)", meanwhile);
    log_line(a->cfg.quiet, "lanray-server", "%s %s in %.2f s%s", r.path, drop ? "opened" : "read again",
             timer_now() - app->loading_t, frames);
    if (drop)
        adopt_dropped(app, a, r.path, r.scene);
    else
        free(r.path);
}

void livescene_step(App *app, const Args *a)
{
    adopt_taken(app);
    take_read(app, a);
    if (!app->watch || !app->scene_path)
        return;
    const double now = timer_now();
    if (watch_changed(app->watch))
        app->edit_t = now;
    if (app->edit_t == 0 || now - app->edit_t < 0.15)
        return;
    app->edit_t = 0;
    request(app, a, app->scene_path, 0);
}

void livescene_drop(App *app, const Args *a, const char *path) { request(app, a, path, 1); }

const char *livescene_opening(const App *app)
{
    if (app->queued && app->queued_drop)
        return file_basename(app->queued);
    if (app->loading && app->loading_drop)
        return file_basename(sceneload_path(app->loading));
    return app->opening_name;
}

void livescene_close(App *app)
{
    if (app->loading) {
        SceneRead r = sceneload_finish(app->loading);
        read_drop(&r);
        app->loading = NULL;
    }
    free(app->queued);
    app->queued = NULL;
}

void livescene_defaults(App *app, const Args *a, const Scene *s)
{
    const int path = s->settings.integrator == INTEGRATOR_PATH;
    if (!a->still.given) {
        const int want[3] = {path, path ? AA_MAX : a->still.aa, path ? 0 : a->still.adaptive};
        int now[3];
        server_still(app->server, &now[0], &now[1], &now[2]);
        if (memcmp(want, now, sizeof want) != 0) /* (a change restarts a converged view) */
            server_set_still(app->server, want[0], want[1], want[2]);
    }
    if (!a->target_given && !(a->render_scale > 0)) {
        const double fps = path ? 10 : 0;
        if (fps != app->win.target_fps) {
            app->win.target_fps = fps;
            if (app->pace.target > 0)
                pace_set_target(&app->pace, fps);
            else
                pace_init(&app->pace, fps); /* from no target: starting at the coarsest scale, as at the start */
            server_set_scale(app->server, app->pace.scale);
        }
    }
}

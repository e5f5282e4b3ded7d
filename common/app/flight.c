/* flight.c - a server's frames along a camera path, of flight.h. */
#include "app/flight.h"

#include <stdlib.h>
#include <string.h>

#include "render/pixel.h"
#include "render/progressive.h"
#include "render/temporal.h"

/* Frame i's settings and the samples its pixels have: a moving frame's
 * (jittered where its history adds it up), or still frame k's. */
static int frame_settings(const RenderSettings *view, const Flight *fl, uint32_t i, int still_step, int temporal,
                          RenderSettings *rs, Err *err)
{
    *rs = *view;
    if (still_step > 0 && fl->still_aa) {
        rs->aa = fl->still_aa, rs->adaptive = 0;
        const int batches = progressive_batches(rs);
        if (!batches)
            return err_set(err, "--server-frame: still frames of %d x %d samples do not go in batches (path-traced, N a power "
                                "of two, 2 or more)", fl->still_aa, fl->still_aa);
        rs->batches = still_step < batches ? still_step : batches;
        return (int)progressive_end(rs->batches);
    }
    if (still_step == 0 && temporal && rs->integrator == INTEGRATOR_PATH)
        rs->jitter = progressive_jitter(rs, i); /* as the server's frame i */
    else if (still_step == 0 && temporal)
        rs->guides = 1; /* Whitted's: its guides for the history (its samples where they were: jittered, the
                         * edges' were noise that a few frames did not add up) */
    return rs->aa * rs->aa;
}

/* The frames a flight's history weighs over a view of settings vs, as
 * the server's (render/temporal.h temporal_history); 0: none. */
static int flight_history(const RenderSettings *vs, const Flight *fl)
{
    return temporal_history(vs, fl->temporal, fl->whitted_temporal);
}

uint64_t flight_bytes(const RenderSettings *rs, const Flight *fl, int width, int height)
{
    if (!flight_history(rs, fl))
        return 0;
    const uint64_t n = (uint64_t)width * (uint64_t)height;
    return temporal_bytes((uint32_t)width, (uint32_t)height) +
           (rs->integrator == INTEGRATOR_WHITTED ? n * (render_colour_bytes(rs) + DENOISE_GUIDE_BYTES) : 0);
}

/* A flight whose instances turn (lanray-server --rotate): a copy of the
 * description whose instances' turns about y grow by `deg` each frame
 * after the first, added frame by frame as the server adds them (the same
 * bits), and the world of the frame, which shares the first's trees. */
typedef struct {
    Scene desc;
    World *world; /* the frame's; NULL before the first turn */
} Turning;

static int turning_start(Turning *tn, const Scene *desc, Err *err)
{
    tn->desc = *desc, tn->world = NULL;
    tn->desc.instances = NULL, tn->desc.instance_cap = 0;
    if (instances_copy(&tn->desc.instances, &tn->desc.instance_cap, desc->instances, desc->instance_count) !=
        desc->instance_count)
        return err_set(err, "out of memory for the turning instances");
    return 0;
}

/* The next frame's world: the instances turned deg more. */
static World *turning_next(Turning *tn, const World *first, real deg, Err *err)
{
    for (uint32_t k = 0; k < tn->desc.instance_count; k++)
        tn->desc.instances[k].rotate.y += deg;
    World *next = world_build(&tn->desc, first, err);
    if (!next)
        return NULL;
    world_destroy(tn->world);
    return tn->world = next;
}

static void turning_end(Turning *tn)
{
    world_destroy(tn->world);
    free(tn->desc.instances);
}

int flight_render(RenderPool *pool, World *w, const Scene *desc, const CameraPath *path, const Flight *fl, int width,
                  int height, uint8_t *pixels, RayStats *st, Err *err)
{
    const View view = w->view;
    const RenderSettings *vs = &view.settings;
    /* a Whitted view's moving frames guided for its history in pixels of
     * their own (the view's have no guides) */
    const int frames = flight_history(vs, fl), whitted = frames && vs->integrator == INTEGRATOR_WHITTED;
    const uint64_t n = (uint64_t)width * (uint64_t)height;
    Temporal *t = NULL;
    uint8_t *guided = NULL;
    if (frames && (!(t = temporal_create(render_pool_pool(pool), (uint32_t)width, (uint32_t)height, frames)) ||
         (whitted && !(guided = malloc(n * (render_colour_bytes(vs) + DENOISE_GUIDE_BYTES)))))) {
        temporal_destroy(t);
        return err_set(err, "out of memory for the history of %dx%d pixels", width, height);
    }
    const double end = (double)camera_path_end(path);
    Camera before = view.camera;
    int still_step = 0, rc = 0;
    Turning turning;
    if (fl->rotate != 0 && turning_start(&turning, desc, err)) {
        temporal_destroy(t);
        free(guided);
        return -1;
    }
    World *fw = w; /* the frame's world */
    for (int i = 1; i <= fl->frames && rc == 0; i++) {
        const double at = (i - 1) * fl->step;
        const Camera cam = path->count ? camera_path_at(path, (real)(at < end ? at : end)) : view.camera;
        /* a turning scene makes every frame after the first a moving one */
        still_step = i > 1 && fl->rotate == 0 && camera_same(&cam, &before) ? still_step + 1 : 0;
        before = cam;
        if (fl->rotate != 0 && i > 1 && !(fw = turning_next(&turning, w, (real)fl->rotate, err))) {
            rc = -1;
            break;
        }
        RenderSettings rs;
        const int samples = frame_settings(&view.settings, fl, (uint32_t)i, still_step, t != NULL, &rs, err);
        if (samples < 0) {
            rc = -1;
            break;
        }
        fw->view.camera = cam, fw->view.settings = rs;
        RayStats part;
        uint8_t *px = rs.guides ? guided : pixels;
        rc = render_span(pool, fw, width, height, 0, n, px, &part, NULL, err);
        ray_stats_add(st, part);
        const Scene *placed = fl->rotate != 0 ? &turning.desc : desc; /* the frame's instances */
        const TemporalFrame tf = {cam,     0, samples, still_step > 0, whitted, placed->instances,
                                  placed->instance_count};
        const uint32_t cb = render_colour_bytes(&rs), bpp = render_pixel_bytes(&rs);
        if (rc == 0 && t && (!whitted || rs.guides))
            temporal_add(t, px, (uint32_t)width, (uint32_t)height, cb, rs.linear, &tf);
        for (uint64_t k = 0; rc == 0 && px != pixels && k < n; k++) /* the colours, as the server's stage strips them */
            memcpy(pixels + k * cb, px + k * bpp, cb);
    }
    w->view = view;
    if (fl->rotate != 0)
        turning_end(&turning);
    temporal_destroy(t);
    free(guided);
    return rc;
}

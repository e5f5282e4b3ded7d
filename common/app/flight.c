/* flight.c - a server's frames along a camera path, of flight.h. */
#include "app/flight.h"

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
    if (still_step == 0 && temporal)
        rs->jitter = progressive_jitter(rs, i); /* as the server's frame i */
    return rs->aa * rs->aa;
}

int flight_render(RenderPool *pool, World *w, const CameraPath *path, const Flight *fl, int width, int height,
                  uint8_t *pixels, RayStats *st, Err *err)
{
    const View view = w->view;
    const int path_traced = view.settings.integrator == INTEGRATOR_PATH && view.settings.denoise;
    Temporal *t = NULL;
    if (fl->temporal && path_traced &&
        !(t = temporal_create(render_pool_pool(pool), (uint32_t)width, (uint32_t)height, fl->temporal)))
        return err_set(err, "out of memory for the history of %dx%d pixels", width, height);
    const double end = (double)camera_path_end(path);
    const uint64_t n = (uint64_t)width * (uint64_t)height;
    Camera before = view.camera;
    int still_step = 0, rc = 0;
    for (int i = 1; i <= fl->frames && rc == 0; i++) {
        const double at = (i - 1) * fl->step;
        const Camera cam = path->count ? camera_path_at(path, (real)(at < end ? at : end)) : view.camera;
        still_step = i > 1 && camera_same(&cam, &before) ? still_step + 1 : 0;
        before = cam;
        RenderSettings rs;
        const int samples = frame_settings(&view.settings, fl, (uint32_t)i, still_step, t != NULL, &rs, err);
        if (samples < 0) {
            rc = -1;
            break;
        }
        w->view.camera = cam, w->view.settings = rs;
        RayStats part;
        rc = render_span(pool, w, width, height, 0, n, pixels, &part, NULL, err);
        ray_stats_add(st, part);
        const TemporalFrame tf = {cam, 0, samples, still_step > 0};
        if (rc == 0 && t)
            temporal_add(t, pixels, (uint32_t)width, (uint32_t)height, render_colour_bytes(&rs), rs.linear, &tf);
    }
    w->view = view;
    temporal_destroy(t);
    return rc;
}

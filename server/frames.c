/* frames.c - a frame of the server's: started (its scene and settings
 * taken, its view and samples chosen: a moving frame at the pace's scale,
 * a still one refining the one before, a path-traced batch adding
 * samples), handed to the scheduler, and once whole, shown in order
 * (brought up from its render scale, through the denoiser's or the
 * history's stage where there is one).  The loop (server.c) calls it; the
 * state is server_impl.h's. */
#include "server_impl.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/log.h"
#include "base/timer.h"
#include "net/wire.h"
#include "render/render.h"
#include "upscale.h"

/* A frame rendered at `scale`, brought up to the full size (upscale.h):
 * smooth (RGB8 or RGBE), or in blocks where asked or where the scratch
 * cannot be had. */
static const uint8_t *scaled_up(Server *s, const uint8_t *pixels, int scale)
{
    if (scale == UPSCALE_ONE)
        return pixels;
    const uint32_t w = (uint32_t)s->cfg.width, h = (uint32_t)s->cfg.height, k = (uint32_t)scale;
    const int smooth = s->cfg.upscale == UPSCALE_SMOOTH, rgbe = s->cbpp == 4;
    /* the finest scale's (1.5) scratch is the most either needs */
    if (smooth && !rgbe && !s->upscale_scratch)
        s->upscale_scratch = malloc(upscale_scratch(w, h, UPSCALE_ONE + 1) * sizeof *s->upscale_scratch);
    if (smooth && rgbe && !s->upscale_rgbe)
        s->upscale_rgbe = malloc(upscale_scratch_rgbe(w, h, UPSCALE_ONE + 1) * sizeof *s->upscale_rgbe);
    if (smooth && !rgbe && s->upscale_scratch)
        upscale_smooth(pixels, s->shown, w, h, k, s->upscale_scratch);
    else if (smooth && rgbe && s->upscale_rgbe)
        upscale_smooth_rgbe(pixels, s->shown, w, h, k, s->upscale_rgbe);
    else
        upscale_blocks(pixels, s->shown, w, h, s->cbpp, k);
    return s->shown;
}

/* The side of the largest pattern of points of the scene's area lights in
 * a view of settings rs (0: no area light). */
static int largest_light_side(const Scene *scene, const RenderSettings *rs)
{
    int side = 0;
    for (uint32_t i = 0; i < scene->light_count; i++)
        if (light_is_area(&scene->lights[i])) {
            const int own = rs->light_samples ? rs->light_samples : scene->lights[i].samples;
            side = own > side ? own : side;
        }
    return side;
}

/* Progressive refinement: the samples of still frame k (1 the first).  A
 * path-traced view sharpens while it is looked at: where the still
 * quality is N x N of N a power of two (`batches`, 2 log2 N + 1 of them,
 * where the server has room for their sums), each still frame renders the
 * next batch of the N x N samples alone, doubling what the picture has,
 * and the server adds them up (the converged frame costs what rendering it
 * alone does); otherwise each doubles the samples a side, 2, 4, 8 ... up
 * to the still quality, rendered whole (4/3 of the converged frame's
 * cost).  The Whitted integrator's takes the still quality at once (after
 * moving frames at a render scale, one frame of the view's own samples
 * first, sharp_first), and then, with still_lights, multiplies its area
 * lights' points a side by four each frame from the largest light's own up
 * to still_lights (its soft shadows'
 * grain: a round lamp of 3 x 3 points leaves penumbrae of ten grey levels
 * and noise; docs/realtime.md).  Whether frame k has the still quality
 * (the converged picture, which is lanray-render's with --aa still_aa and,
 * with still_lights, --light-samples still_lights). */
static int refine_step(const ServerConfig *c, const Scene *scene, int k, RenderSettings *rs, int batches,
                       int sharp_first)
{
    if (batches > 0) { /* the batches of N x N, added up (render/progressive.h) */
        rs->aa = c->still_aa;
        rs->adaptive = 0;
        rs->batch = k <= batches ? k : 0;
        return k >= batches;
    }
    /* after moving frames at a render scale, a Whitted view's first still
     * frame is the view's own samples, whole: a sharp picture in a third
     * of the still quality's time (the demo's 1024x768, 2 cores: 0.4 s
     * against 1.1 s), where the window would have shown the last moving
     * frame's blur until then */
    if (sharp_first && rs->integrator == INTEGRATOR_WHITTED &&
        (rs->aa != c->still_aa || rs->adaptive != c->still_adaptive)) {
        if (k == 1)
            return 0;
        k--;
    }
    const int side = k < 8 ? 2 << (k - 1) : AA_MAX;
    if (rs->integrator == INTEGRATOR_PATH && side < c->still_aa) {
        rs->aa = side;
        rs->adaptive = 0;
        return 0;
    }
    rs->aa = c->still_aa;
    rs->adaptive = c->still_adaptive;
    const int own = largest_light_side(scene, rs);
    if (rs->integrator == INTEGRATOR_PATH || c->still_lights == 0 || own == 0) /* no points to add */
        return 1;
    if (k == 1)
        return 0;
    /* own x 4^(k - 1), stopped at still_lights (k may grow without end):
     * sixteen times the points a frame, so that the frames before the
     * converged one cost a fifteenth of it, not a third as doubling a side
     * did (the demo's lamp, 3 x 3 to 12 x 12 at once: converged a fifth
     * sooner), while in a window the last frame shows as it comes */
    int lights = own;
    for (int j = 1; j < k && lights < c->still_lights; j++)
        lights *= 4;
    rs->light_samples = lights < c->still_lights ? lights : c->still_lights;
    return rs->light_samples == c->still_lights;
}

/* Whether a frame of settings rs samples adaptively (anti-aliasing, or
 * area lights probed first), so that each segment samples its neighbour
 * lines' centres too. */
static int adaptive_frame(const RenderSettings *rs)
{
    return (rs->adaptive && rs->aa > 1) || rs->light_sampling == LIGHTS_ADAPTIVE;
}

/* The current frame's buffer (free: its frame has not started) made for
 * need bytes a pixel; 0 where there is no memory for it. */
static int frame_room(Server *s, uint32_t need)
{
    if (s->frame_cap >= need)
        return 1;
    uint8_t *p = realloc(s->pixels, (size_t)s->cfg.width * s->cfg.height * need);
    if (!p)
        return 0;
    s->pixels = p;
    s->frame_cap = need;
    free(s->spare_pixels); /* made smaller: made again when wanted */
    s->spare_pixels = NULL;
    return 1;
}

/* The batches a still frame of the view's settings at the still quality
 * would take (render/progressive.h), with the frames' buffers grown to
 * hold their sums and the sums' own made; 0 where its samples do not go
 * in batches, the frame is too large, or there is no memory for them
 * (each still frame is then rendered whole). */
static int still_batches(Server *s)
{
    RenderSettings rs = s->view.settings;
    rs.aa = s->cfg.still_aa, rs.adaptive = s->cfg.still_adaptive, rs.batch = 1;
    const int batches = progressive_batches(&rs);
    const size_t n = (size_t)s->cfg.width * s->cfg.height;
    const uint32_t need = render_pixel_bytes(&rs);
    /* a frame whose sums would not fit one DATA packet is rendered whole
     * (12 bytes a pixel, 48 denoised: 4K UHD fits, and denoised 1920x1080) */
    if (!batches || (uint64_t)n * need > PROTO_MAX_PIXELS)
        return 0;
    if (!s->acc_sums) {
        s->acc_sums = calloc(n, progressive_reals(&rs) * sizeof(real));
        s->acc_px = malloc(n * s->bpp);
        if (!s->acc_sums || !s->acc_px) {
            free(s->acc_sums), free(s->acc_px);
            s->acc_sums = NULL, s->acc_px = NULL;
            return 0;
        }
        /* a 1024x768 frame's batch took the loop 17 ms alone (39 with
         * guides): its pixels are added on up to 8 threads (without them, on
         * the loop's) */
        const long cores = sysconf(_SC_NPROCESSORS_ONLN);
        if (!s->acc_pool) /* kept through a change of size */
            s->acc_pool = cores > 1 ? pool_create(cores < 8 ? (int)cores : 8, NULL) : NULL;
    }
    return frame_room(s, need) ? batches : 0;
}

/* A Whitted view's history (server_temporal): the stage that adds its
 * moving frames up, without a filter, made at the first of them (a
 * server that never moves has none: about 150 bytes a pixel), and the room
 * for its guided pixels; 0 where there is no memory for them (logged
 * once: the frames then go without). */
static int history_stage(Server *s)
{
    if (s->stage)
        return frame_room(s, s->cbpp + DENOISE_GUIDE_BYTES);
    Err err = {{0}};
    s->stage = server_stage_make(s, s->cfg.width, s->cfg.height, 0, s->cfg.whitted_temporal, &err);
    if (s->stage && !frame_room(s, s->cbpp + DENOISE_GUIDE_BYTES))
        err_set(&err, "out of memory for %dx%d guided pixels", s->cfg.width, s->cfg.height);
    if (s->stage && !err.msg[0])
        return 1;
    log_line(s->cfg.quiet, "lanray-server", "moving frames without their history: %s", err.msg);
    denoise_stage_destroy(s->stage);
    s->stage = NULL;
    s->history_failed = 1;
    return 0;
}

/* server_set_size, taken where no frame is in flight nor in the stage
 * (server_step waits for that): the frames' buffers made again at the new
 * size (those made when wanted, freed), the stage's filter and history
 * too; the view starts again (the next frame is not a still one).  Where
 * there is no memory for them the size stays, said in the log. */
static void apply_size(Server *s)
{
    const int w = s->next_width, h = s->next_height;
    s->next_width = s->next_height = 0;
    const size_t n = (size_t)w * h;
    uint8_t *px = malloc(n * s->frame_cap), *shown = malloc(n * s->cbpp);
    uint8_t *stripped = s->stripped ? malloc(n * s->cbpp) : NULL;
    Err err = {{0}};
    DenoiseStage *stage = s->filters ? server_stage_make(s, w, h, 1, s->cfg.temporal, &err) : NULL;
    if (!px || !shown || (s->stripped && !stripped) || (s->filters && !stage)) {
        free(px), free(shown), free(stripped);
        denoise_stage_destroy(stage);
        log_line(s->cfg.quiet, "lanray-server", "%dx%d frames: %s; they stay %dx%d", w, h,
                 err.msg[0] ? err.msg : "out of memory", s->cfg.width, s->cfg.height);
        return;
    }
    free(s->pixels), free(s->shown), free(s->stripped);
    s->pixels = px, s->shown = shown, s->stripped = stripped;
    denoise_stage_destroy(s->stage); /* a Whitted view's history: made again at its next moving frame */
    s->stage = stage;
    uint8_t **made_later[] = {&s->spare_pixels, &s->peek_px, &s->acc_px};
    for (size_t i = 0; i < sizeof made_later / sizeof *made_later; i++)
        free(*made_later[i]), *made_later[i] = NULL;
    free(s->acc_sums), s->acc_sums = NULL, s->acc_batch = 0;
    free(s->upscale_scratch), s->upscale_scratch = NULL;
    free(s->upscale_rgbe), s->upscale_rgbe = NULL;
    sched_destroy(s->spare_sched), s->spare_sched = NULL;
    s->cfg.width = w, s->cfg.height = h;
    s->sched_cfg.width = (uint32_t)w, s->sched_cfg.height = (uint32_t)h;
    s->sched_cfg.min_pixels = (uint32_t)(w / 4 > 0 ? w / 4 : 1);
    s->settings_id++;
}

int frames_start(Server *s, Err *err)
{
    if (s->next_width)
        apply_size(s);
    server_apply_pending(s);
    if (s->dirty) { /* a new description: checked, encoded once, numbered */
        s->scene_blob.len = 0;
        if (scene_check(s->scene, err) ||
            wire_encode_scene(s->scene, s->assets->a, s->assets->a + s->scene->model_count, &s->scene_blob, err))
            return -1;
        s->scene_id++;
        s->dirty = 0;
    }
    /* still: nothing moved since the frame before, which the view then refines */
    s->still = s->frame > 0 && s->scene_id == s->last_scene_id && s->settings_id == s->last_settings_id &&
               camera_same(&s->view.camera, &s->last_camera);
    s->last_camera = s->view.camera;
    s->last_scene_id = s->scene_id;
    s->last_settings_id = s->settings_id;
    s->frame_t0 = timer_now();
    s->still_step = s->still ? s->still_step + 1 : 0;
    if (s->still_step == 1)
        s->sharp_first = s->scale > UPSCALE_ONE; /* the frame before's scale */
    View v = s->view;
    const int batches = s->still && s->cfg.refine ? still_batches(s) : 0;
    s->converged = s->still && (!s->cfg.refine ||
                                refine_step(&s->cfg, s->scene, s->still_step, &v.settings, batches, s->sharp_first));
    if (!s->still && s->cfg.moving_lights >= 0)
        v.settings.light_sampling = (LightSampling)s->cfg.moving_lights;
    if (!s->still && s->cfg.moving_light_samples > 0)
        v.settings.light_samples = s->cfg.moving_light_samples;
    /* a path-traced moving frame whose history adds it up: another of its
     * pixels' samples each (the frame to come is s->frame + 1); a Whitted
     * one near the full size carries its guides there (at render scales 2
     * to 4 its history blurred more than it smoothed: the demo's flight
     * 1-2% further from the full-quality frames, and slower) */
    if (!s->still && server_temporal_frames(s, &v.settings)) {
        if (v.settings.integrator == INTEGRATOR_PATH)
            v.settings.jitter = progressive_jitter(&v.settings, s->frame + 1);
        else if (s->next_scale <= HISTORY_SCALE)
            v.settings.guides = history_stage(s);
    }
    s->frame_cam = v.camera;
    s->frame_epoch = (uint64_t)s->edit_id << 32 | s->settings_id;
    s->frame_placed = s->older.id ? 1 - s->older.placed : 0;
    Placed *p = &s->placed[s->frame_placed]; /* none where memory ran out: the history follows no instance */
    p->count = instances_copy(&p->inst, &p->cap, s->scene->instances, s->scene->instance_count);
    s->frame_rs = v.settings;
    s->frame_bpp = render_pixel_bytes(&v.settings);
    /* a moving frame at the render scale, a still one whole */
    const uint32_t last_lines = s->fh;
    s->scale = s->still ? UPSCALE_ONE : s->next_scale;
    s->fw = upscale_side((uint32_t)s->cfg.width, (uint32_t)s->scale);
    s->fh = upscale_side((uint32_t)s->cfg.height, (uint32_t)s->scale);
    sched_set_size(s->sched, s->fw, s->fh);
    s->blob.len = 0;
    if (wire_encode_view(&v, &s->blob, err))
        return -1;
    s->view_len = (uint32_t)s->blob.len;
    s->blob_has_scene = 0;
    s->frame++;
    s->in_frame = 1;
    uint32_t n = server_client_count(s);
    double work;
    const SchedStats st = server_stats_all(s);
    double o = measure_frame_start(&s->m, timer_now(), n, server_bytes(s), st.duplicate_pixels, st.segments,
                                   s->auto_segment, &work);
    /* a segment of an adaptive frame renders the centre samples of the
     * lines just above and below it again (render.c, the key lines): up to
     * two lines of the last frame's work more a segment, which the measured
     * gaps do not show (they land in render times) */
    if (adaptive_frame(&v.settings) && last_lines > 0)
        o += 2.0 * work / last_lines;
    sched_start_frame(s->sched, s->frame, n, s->auto_segment, work, o);
    for (uint32_t i = 0; i < s->nclients; i++)
        if (s->clients[i]->state == CLIENT_ACTIVE && !s->clients[i]->closing)
            server_send_update(s, s->clients[i]);
    return 0;
}

/* The next frame, started while the current one still has segments out:
 * the current one's state moves to `older` (its scheduler and pixels stay
 * live until it is shown), the new one takes the spare ones.  0 where it
 * does not start (no memory for a second frame, or the application holds
 * it back), 1 where it did, -1 on an error. */
int frames_start_ahead(Server *s, Err *err)
{
    if (s->next_width) /* a new size: after the frames in flight */
        return 0;
    if (!s->spare_sched && !(s->spare_sched = sched_create(&s->sched_cfg)))
        return 0;
    if (!s->spare_pixels && !(s->spare_pixels = calloc((size_t)s->cfg.width * s->cfg.height, s->frame_cap)))
        return 0;
    if (s->next_fn && !s->next_fn(s->next_ctx, s->frame + 1, 1))
        return 0;
    s->older = (Older){s->frame,    s->sched,    s->pixels,    s->fw,        s->fh,        s->scale,
                       s->still,    s->converged, s->frame_t0, s->frame_rs, s->frame_bpp, s->frame_cap,
                       s->frame_cam, s->frame_epoch, s->frame_placed};
    sched_set_segment_lines(s->spare_sched, sched_config(s->sched)->segment_lines);
    s->sched = s->spare_sched;
    s->pixels = s->spare_pixels;
    s->spare_sched = NULL;
    s->spare_pixels = NULL;
    for (uint32_t i = 0; i < s->nclients; i++)
        s->clients[i]->older_ok = s->clients[i]->frame_sent == s->older.id;
    s->frames_ahead++;
    return frames_start(s, err) ? -1 : 1;
}

/* A range of a batch frame's pixels added to the sums before it and
 * encoded (progressive_frame_add), for pool_for. */
typedef struct {
    const RenderSettings *rs;
    real *acc;
    const uint8_t *sums;
    uint8_t *out;
    uint32_t bpp;
} BatchAdd;

static void batch_add_range(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const BatchAdd *b = ctx;
    const uint32_t reals = progressive_reals(b->rs);
    progressive_frame_add(b->rs, b->acc + lo * reals, b->sums + lo * reals * sizeof(real), (size_t)(hi - lo),
                          b->out + lo * b->bpp);
}

/* The samples a pixel of a frame of settings rs shows: a batch's, all
 * those so far (render/progressive.h); a whole frame's, N x N (adaptive:
 * at most). */
static int frame_samples(const RenderSettings *rs)
{
    return rs->batch ? (int)progressive_end(rs->batch) : rs->aa * rs->aa;
}

/* What a frame's showing needs, and its history's adding up. */
static StageFrame stage_frame(const Server *s, uint32_t id, int scale, int still, int converged, double t0,
                              const RenderSettings *rs, const Camera *cam, uint64_t epoch, int placed)
{
    const int temporal = rs->integrator == INTEGRATOR_PATH ? server_temporal_frames(s, rs) > 0 : rs->guides;
    const Placed *p = &s->placed[placed];
    return (StageFrame){id, scale, still, converged, t0, frame_samples(rs), temporal, *cam, epoch, p->inst, p->count};
}

/* A finished frame to the application: the panel's and the pace's
 * figures first, then the callback. */
static void show_frame(Server *s, const StageFrame *f, const uint8_t *pixels, FrameDoneFn done, void *ctx)
{
    const double now = timer_now();
    measure_frame_end(&s->m, now);
    measure_latency(&s->m, now - f->t0);
    s->last_frame_s = now - f->t0;
    for (uint32_t i = 0; i < s->nclients; i++) {
        s->clients[i]->last_frame_pixels = s->clients[i]->frame_pixels;
        s->clients[i]->frame_pixels = 0;
    }
    s->shown_still = f->still;
    s->shown_converged = f->converged;
    s->shown_scale = f->scale;
    s->shown_samples = f->samples;
    if (done)
        done(ctx, f->id, scaled_up(s, pixels, f->scale));
}

/* The frame the denoise stage filtered, shown (wait: once it is); 1 where
 * one was. */
static int show_filtered(Server *s, int wait, FrameDoneFn done, void *ctx)
{
    const uint8_t *colours;
    StageFrame f;
    if (!s->stage || !denoise_stage_take(s->stage, wait, &colours, &f))
        return 0;
    show_frame(s, &f, colours, done, ctx);
    return 1;
}

/* A finished frame: shown, or with settings denoise handed to the stage to
 * be filtered at its render scale (then brought up) and shown once it is,
 * or with settings guides to be added to its history (the frame before
 * first: frames are shown in order). */
static void frame_finished(Server *s, const StageFrame *f, const uint8_t *pixels, const RenderSettings *rs,
                           FrameDoneFn done, void *ctx)
{
    if (rs->batch) { /* a batch of a still's samples: added to the ones before, their picture shown */
        if (rs->batch != 1 && rs->batch != s->acc_batch + 1) {
            /* the batch before was lost (a frame dropped when the clients
             * that had it left): the still frames start again from batch 1 */
            log_line(s->cfg.quiet, "lanray-server", "frame %u: batch %d of the still's samples after batch %d: not shown",
                     f->id, rs->batch, s->acc_batch);
            s->still_step = 0;
            s->converged = 0;
            return;
        }
        const size_t n = (size_t)s->cfg.width * s->cfg.height;
        if (rs->batch == 1)
            memset(s->acc_sums, 0, n * progressive_reals(rs) * sizeof(real));
        s->acc_batch = rs->batch;
        BatchAdd b = {rs, s->acc_sums, pixels, s->acc_px, s->bpp};
        pool_for(s->acc_pool, n, 8192, batch_add_range, &b);
        pixels = s->acc_px;
    }
    if (s->stage && denoise_stage_holds(s->stage)) /* the frame before first */
        show_filtered(s, 1, done, ctx);
    if (!s->stage || !render_guided(rs)) { /* no guides: nothing for the stage */
        show_frame(s, f, pixels, done, ctx);
        return;
    }
    const uint32_t fw = upscale_side((uint32_t)s->cfg.width, (uint32_t)f->scale),
                   fh = upscale_side((uint32_t)s->cfg.height, (uint32_t)f->scale);
    if (s->raw_view) { /* the colours alone, unfiltered */
        for (size_t i = 0; i < (size_t)fw * fh; i++)
            memcpy(s->stripped + i * s->cbpp, pixels + i * s->bpp, s->cbpp);
        show_frame(s, f, s->stripped, done, ctx);
        return;
    }
    denoise_stage_put(s->stage, pixels, fw, fh, s->view.settings.linear, f);
}

/* Frames shown in order: the older of two in flight first.  An older frame
 * with work left that no client still connected can render (all that held
 * its view left) is dropped, not waited for. */
void frames_finish(Server *s, FrameDoneFn done, void *ctx)
{
    show_filtered(s, 0, done, ctx);
    if (s->older.id) {
        Older *o = &s->older;
        int stranded = !sched_frame_done(o->sched) && sched_has_fresh(o->sched);
        for (uint32_t i = 0; stranded && i < s->nclients; i++)
            stranded = !(s->clients[i]->state == CLIENT_ACTIVE && !s->clients[i]->closing && s->clients[i]->older_ok);
        if (!sched_frame_done(o->sched) && !stranded)
            return;
        if (stranded) {
            s->frames_dropped++;
            log_line(s->cfg.quiet, "lanray-server", "frame %u dropped: the clients that had its view left", o->id);
        } else {
            const StageFrame f =
                stage_frame(s, o->id, o->scale, o->still, o->converged, o->t0, &o->rs, &o->cam, o->epoch, o->placed);
            frame_finished(s, &f, o->pixels, &o->rs, done, ctx);
        }
        s->spare_sched = o->sched;
        if (o->cap == s->frame_cap) { /* else made before the buffers grew */
            s->spare_pixels = o->pixels;
        } else {
            free(o->pixels);
            s->spare_pixels = NULL;
        }
        *o = (Older){0};
    }
    if (s->in_frame && sched_frame_done(s->sched)) {
        s->in_frame = 0;
        const StageFrame f = stage_frame(s, s->frame, s->scale, s->still, s->converged, s->frame_t0, &s->frame_rs,
                                         &s->frame_cam, s->frame_epoch, s->frame_placed);
        frame_finished(s, &f, s->pixels, &s->frame_rs, done, ctx);
    }
}

/* flight.h - the frames a farm shows along a camera path, made by one
 * program (lanray-render --server-frame), so that each of a server's frames in
 * a flight can be checked bit for bit.
 *
 * Frame i shows the path at (i - 1) x step seconds (clamped to its end),
 * as lanray-server --path --path-step does (without a path, the scene's
 * camera: one moving frame, then still ones); a frame whose camera is the
 * frame before's is a still one (its scene and settings do not change
 * here).  A moving frame is rendered at the view's quality, path-traced
 * and denoised each taking another of its pixels' samples (settings
 * jitter) and added to the frames before by a reprojected history
 * (render/temporal.h), Whitted's (not denoised) added up too, guided
 * (settings guides; the server's near the full size); still frames take
 * still_aa x still_aa in the batches of render/progressive.h, still frame
 * k the first k of them (lanray-render --still-frame k). */
#ifndef LANRAY_FLIGHT_H
#define LANRAY_FLIGHT_H

#include "render/render.h"
#include "render/temporal.h"
#include "scene/camera_path.h"

typedef struct {
    int frames;     /* how many; 0: none (one frame at --at) */
    double step;    /* seconds of the path a frame */
    int still_aa;   /* still frames' N x N, N a power of two (0: the moving frames' quality) */
    int temporal;   /* the frames a pixel's history weighs at most (0: none) */
    int whitted_temporal; /* ... of a Whitted view (0: none) */
    double rotate;        /* degrees the instances turn about y each frame after the first (lanray-server --rotate) */
} Flight;

/* lanray-render's options for a flight; the server has --path-step,
 * --still-aa, --temporal and --whitted-temporal of the same meaning. */
#define FLIGHT_OPTS(f) \
    {.name = "--server-frame", .kind = OPT_INT, .dst = &(f)->frames, .arg = "K", .lo = 0, .hi = 100000, .def = "0", \
     .help = "the picture of a server's frame K of the scene, or flying --path (lanray-server --path-step, " \
             "--still-aa, --temporal): its frames 1 to K rendered, the last written; 0 = one frame at --at"}, \
    {.name = "--path-step", .kind = OPT_REAL, .dst = &(f)->step, .arg = "S", .rlo = 0, .rhi = 1e6, .def = "0", \
     .help = "--server-frame: seconds of the path a frame (frame i shows it at (i - 1) x S)"}, \
    {.name = "--still-aa", .kind = OPT_INT, .dst = &(f)->still_aa, .arg = "N", .lo = 0, .hi = AA_MAX, .def = "0", \
     .help = "--server-frame: the still frames' N x N samples, N a power of two, in batches that double them; 0 = as " \
             "the moving ones"}, \
    CLI_TEMPORAL_OPT(&(f)->temporal, "--server-frame, path-traced and denoised: "), \
    {.name = "--rotate", .kind = OPT_REAL, .dst = &(f)->rotate, .arg = "DEG", .rlo = -360, .rhi = 360, .def = "0", \
     .help = "--server-frame: the instances turn DEG degrees about y each frame after the first (lanray-server " \
             "--rotate); those frames are moving ones"}, \
    CLI_WHITTED_TEMPORAL_OPT(&(f)->whitted_temporal, "--server-frame, ")

/* --whitted-temporal, the server's and lanray-render's */
#define CLI_WHITTED_TEMPORAL_OPT(to, what) \
    {.name = "--whitted-temporal", .kind = OPT_INT, .dst = to, .arg = "F", .lo = 0, .hi = TEMPORAL_MAX_FRAMES, \
     .def = "2", \
     .help = what "Whitted's moving frames near the full size (render scale 1 or 1.5) added to the frames before " \
                  "them (up to F, reprojected " \
                  "onto the moving camera, held within each frame's own light about a pixel): smoother shadows " \
                  "and edges; 0 = none"}

/* --temporal, the server's and lanray-render's */
#define CLI_TEMPORAL_OPT(to, what) \
    {.name = "--temporal", .kind = OPT_INT, .dst = to, .arg = "F", .lo = 0, .hi = TEMPORAL_MAX_FRAMES, .def = "4", \
     .help = what "each moving frame takes another sample of its pixels, added to the frames before it (up to F " \
                  "of them, reprojected onto the moving camera); 0 = none"}

/* The bytes of a flight's history over frames of settings rs (its guided
 * frame too, for a Whitted view's); 0 where it has none. */
uint64_t flight_bytes(const RenderSettings *rs, const Flight *fl, int width, int height);

/* Renders the flight's frames along path (no keys: at w's camera) over w (its view's camera and settings
 * changed on the way, put back at the end; with fl->rotate, over worlds of
 * desc, w's description, its instances turned) into pixels (width x height,
 * render_pixel_bytes of w's settings): the last frame's pixels as the
 * server has them before it denoises them.  0, or -1 with err (a still
 * quality that does not go in batches, memory). */
int flight_render(RenderPool *pool, World *w, const Scene *desc, const CameraPath *path, const Flight *fl, int width,
                  int height, uint8_t *pixels, RayStats *st, Err *err);

#endif

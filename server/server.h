/* server.h - the render server: one poll() event loop serving any number of
 * clients, driving the scheduler and assembling frames.
 *
 * The caller owns the scene and the display; the server calls back when a
 * frame is complete.  Nothing here blocks: server_step waits at most the
 * given time for network events and returns, so a display loop can run
 * between steps. */
#ifndef LANRAY_SERVER_H
#define LANRAY_SERVER_H

#include <stdint.h>

#include "scheduler.h"
#include "net/asset.h"
#include "scene/scene.h"

/* The largest frame side a server assembles (lanray-render goes further). */
#define SERVER_MAX_SIDE 16384

typedef struct {
    const char *listen_addr; /* default 127.0.0.1 */
    int port;
    const char *token;       /* NULL: no authentication (loopback or --insecure) */
    int insecure;            /* allow a non-loopback address without a token */
    int width, height;
    uint32_t segment_lines;   /* 0: chosen automatically from client count and measured segment times */
    SchedTailRule tail;
    double stall_timeout;     /* seconds without a result while holding work: disconnect */
    double handshake_timeout; /* seconds to finish the handshake */
    int quiet;
    uint32_t warmup;          /* frames left out of the summary (the first carries the assets) */
    /* progressive refinement: a frame whose camera and scene are the
     * previous frame's is rendered with these samples (the still quality,
     * lanray-render's picture bit for bit), a frame that moved with the
     * scene's own (refine 0: every frame with the scene's) */
    int refine, still_aa, still_adaptive;
    /* and then, for the Whitted integrator, the area lights' points four
     * times a side each still frame up to still_lights x still_lights (settings
     * light_samples: soft shadows that converge); 0: the scene's own */
    int still_lights;
    /* the light sampling (LightSampling) of the frames that are not still
     * ones; -1: the scene's (lanray-server --moving-lights) */
    int moving_lights;
    /* ... and its area lights' points a side (settings light_samples); 0:
     * the view's (lanray-server --moving-light-samples) */
    int moving_light_samples;
    /* how clients are asked to code their pixels (net/pixcodec.h: PIX_RAW,
     * PIX_LZ4, PIX_ZSTD | PIX_PREDICT; lanray-server --compress); a client
     * without that codec sends them raw */
    uint32_t coding;
    /* pipelined frames: the next frame starts (its UPDATE goes out) as
     * soon as the current one has no fresh work left, if the application's
     * FrameNextFn lets it, so that clients with nothing left render it
     * rather than wait or duplicate; frames are still shown in order */
    int pipeline;
    /* how a frame at a render scale is brought to the full size for the
     * callback (UpscaleKind, upscale.h: smooth, the default, or blocks;
     * lanray-server --upscale) */
    int upscale;
    /* threads of the denoiser's passes, where the scene's settings say
     * denoise (each frame is filtered by its pixels' guides before it is
     * shown: render/denoise.h); 0: one per core */
    int denoise_threads;
    /* path-traced and denoised: the frames a pixel's history weighs while
     * the camera moves (each moving frame another sample of its pixels,
     * added to the frames before, reprojected: render/temporal.h); 0: none */
    int temporal;
    /* ... and Whitted's, its moving frames near the full size (render
     * scale 1 or 1.5) carrying their guides for it (settings guides) */
    int whitted_temporal;
} ServerConfig;

typedef struct Server Server;

/* Called with each completed frame: width*height pixels of RGB8, or of RGBE
 * where the scene's settings say hdr (render_colour_bytes); with settings
 * denoise, filtered. */
typedef void (*FrameDoneFn)(void *ctx, uint32_t frame, const uint8_t *pixels);

/* Called before a frame starts (its number: frame), for the application's
 * per-frame changes (a camera path, an animation), which that frame takes.
 * `ahead`: the frame before it is not finished yet (pipelined).  Return 0
 * to let it wait, where it is not wanted or (ahead) its view is not known
 * yet: the call comes again later. */
typedef int (*FrameNextFn)(void *ctx, uint32_t frame, int ahead);

/* Called as a still frame's segment comes, where the frame is the next to
 * be shown and whole (no render scale) and its pixels are what will be
 * shown (not filtered, not added to a history): its pixels [first, first +
 * count) of the full-size frame in the FrameDoneFn's format, for a window
 * to show the picture refining as the clients make it (a path-traced
 * still's batch: with the batches before, as the finished frame will be).
 * The FrameDoneFn still comes with the whole frame. */
typedef void (*FrameLinesFn)(void *ctx, uint32_t frame, uint32_t first, uint32_t count, const uint8_t *pixels);

Server *server_create(const ServerConfig *cfg, Scene *scene, Err *err);
void server_on_next(Server *s, FrameNextFn next, void *ctx);
void server_on_lines(Server *s, FrameLinesFn lines, void *ctx);
void server_destroy(Server *s);
/* The camera of the next frame (the window's moves), and the instances
 * turned by `degrees` about y from the next frame on (its animation): held
 * until that frame starts, so that the scene a frame was sent from is
 * never changed while the frame is under way. */
void server_set_camera(Server *s, const Camera *c);
void server_turn_instances(Server *s, real degrees);
/* The description of the frames to come (a scene file read again) and its
 * assets (asset_make_scene's, which the server owns from now on): the
 * assets a client lacks are sent to it at once, and the frames go on
 * showing the scene before until every client holds them decoded, or
 * AHEAD_WAIT_S passed (ahead.c); it is taken at the next frame's start
 * after that.  A scene handed over before the one before was taken
 * replaces it.  The caller keeps ownership of the scenes and may free the
 * old one once server_scene returns the new one. */
void server_set_scene(Server *s, Scene *next, Asset *assets, uint32_t nassets);
Scene *server_scene(const Server *s);
/* The frames' size from the next frame on (the window's): taken once the
 * frames in flight are shown, their buffers (and a denoised view's
 * history) made again at it; the view starts again from a moving frame.
 * server_size says the size of the newest frame started, which is the
 * size of every frame the FrameDoneFn and FrameLinesFn get until the next
 * change is taken. */
void server_set_size(Server *s, int width, int height);
void server_size(const Server *s, int *width, int *height);
/* Whether a new camera, a turn, a new scene or a new size waits for the next frame. */
int server_changes_pending(const Server *s);
/* The camera the next frame starts from. */
Camera server_camera(const Server *s);
/* The quality settings of the frames to come (the window's knobs): held
 * until the next frame starts, which then is not a still one. */
void server_set_settings(Server *s, const RenderSettings *rs);
RenderSettings server_settings(const Server *s);
/* Progressive refinement's still quality (ServerConfig refine, still_aa,
 * still_adaptive), changed from the window. */
void server_set_still(Server *s, int refine, int aa, int adaptive);
void server_still(const Server *s, int *refine, int *aa, int *adaptive);
/* ServerConfig still_lights: the area lights' points a side still frames refine up to (0: their own). */
int server_still_lights(const Server *s);
/* The moving frames' light sampling (ServerConfig moving_lights), from the
 * window; server_moving_lights says what they take (LightSampling: the
 * config's, else the settings'). */
void server_set_moving_lights(Server *s, int lights);
int server_moving_lights(const Server *s);
/* ServerConfig moving_light_samples: the area lights' points a side in moving frames (0: the view's). */
int server_moving_light_samples(const Server *s);
/* How frames at a render scale fill the window from the next one shown
 * (UpscaleKind: the U key); server_upscale says it. */
void server_set_upscale(Server *s, int upscale);
int server_upscale(const Server *s);
/* The active clients as the window's panel shows them: each one's share of
 * the last finished frame's pixels and its rate over that frame, in lines
 * of the frame's width a second.  Returns how many were written (<= max). */
typedef struct {
    int id;
    char addr[64];
    uint32_t threads;
    double share, lines_per_s;
} ServerClientInfo;
uint32_t server_clients_info(const Server *s, ServerClientInfo *out, uint32_t max);
/* The last finished frame's time, from its start to its last pixels, seconds. */
double server_last_frame_time(const Server *s);
/* The render scale of the moving frames to come, in quarter steps (upscale.h:
 * UPSCALE_ONE, 4, every pixel, to UPSCALE_MAX, 32, a scale of 8): the
 * clients render a frame of upscale_side(width, scale) x upscale_side(height,
 * scale) pixels and the server shows it brought up to the full size.  A
 * still frame is rendered whole. */
void server_set_scale(Server *s, int scale);
/* The scale of the frame shown last, in quarter steps (in the FrameDoneFn: that frame's). */
int server_frame_scale(const Server *s);
/* Whether the frame shown last was a still one: its camera and scene those
 * of the frame before (rendered with the still quality when refining). */
int server_frame_still(const Server *s);
/* Whether the frame shown last, and the newest frame started, is the
 * converged picture: a still frame with the still quality (a path-traced
 * view refines over several still frames first: refine_step in server.c),
 * or any still frame without refinement. */
int server_frame_converged(const Server *s);
/* The samples a pixel of the frame shown last: a path-traced still's
 * batches so far, else its settings' N x N (at most, adaptive). */
int server_frame_samples(const Server *s);
/* Whether the server denoises its frames (settings denoise), and whether
 * they are shown so (1, the default) or raw (0: the window's X key, to see
 * what the filter took out; the guides still travel); a change renders the
 * view again. */
int server_denoises(const Server *s);
int server_denoise_shown(const Server *s);
/* The frames a moving pixel's history weighs (--temporal, where the view
 * is path-traced and denoised; --whitted-temporal, Whitted's:
 * render/temporal.h); 0: none. */
int server_temporal(const Server *s);
void server_set_denoise_shown(Server *s, int shown);
int server_newest_converged(const Server *s);
/* One round of the event loop, waiting at most timeout_ms.  Starts a new frame
 * when the previous one is done and clients are connected, unless paused. */
int server_step(Server *s, int timeout_ms, FrameDoneFn done, void *ctx, Err *err);
/* Frames stop being started (the current one still completes). */
void server_pause(Server *s, int paused);
int server_port(const Server *s);
/* The address and port listened on, as "127.0.0.1:7878" or "[::1]:7878". */
const char *server_address(const Server *s);
uint32_t server_client_count(const Server *s);
/* Takes an already connected, non-blocking socket as a new client (accept()
 * hands its sockets here; tests and the packet fuzzer hand it one end of a
 * socketpair).  Returns 0, or -1 with the socket closed and the reason logged
 * when the server is full or out of memory. */
int server_adopt(Server *s, int fd, const char *addr);
/* Per-client statistics as a table, to stdout. */
void server_print_stats(const Server *s);
/* Frames, rate and what a frame cost, in two lines to stdout; with
 * `machine`, also one "summary key=value ..." line for benchmarks: frames,
 * wall time from the first frame's start to the last one's end, FPS,
 * clients, their busy time and efficiency (busy / (clients x wall)), idle
 * time, duplicated lines and bytes per frame, segment size, overheads. */
void server_print_summary(const Server *s, int machine);
/* The segment size the next frame will use. */
uint32_t server_segment_lines(const Server *s);

#endif

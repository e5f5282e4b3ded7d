/* server_impl.h - the server's state, shared by server.c (the loop, the
 * clients and their packets) and frames.c (a frame started, refined,
 * finished and shown).  Not for other modules: server.h is the server's
 * face. */
#ifndef LANRAY_SERVER_IMPL_H
#define LANRAY_SERVER_IMPL_H

#include "server.h"

#include "denoisestage.h"
#include "measure.h"
#include "net/asset.h"
#include "upload.h"
#include "net/conn.h"
#include "net/pixcodec.h"
#include "scene/world.h"
#include "scheduler.h"

/* The coarsest render scale (quarter steps: 1.5) whose Whitted moving frames
 * are added up: at 1.5 the demo's flight came 4% closer (SSIM 0.979 ->
 * 0.980), at 2 as close as without, at 3 and 4 further. */
#define HISTORY_SCALE 6

#define MAX_CLIENTS 1024

typedef enum { CLIENT_HANDSHAKE, CLIENT_ACTIVE } ClientState;

/* An asset sent to a client, and whether its HAVE came. */
typedef struct {
    uint8_t hash[PROTO_HASH];
    int have;
} SentAsset;

/* How long a new scene waits for its assets to be taken in by every
 * client (ahead.c) before its frames start without that client. */
#define AHEAD_WAIT_S 30.0

typedef struct {
    int id;
    Conn conn;
    ClientState state;
    char addr[64];
    uint8_t nonce[PROTO_NONCE];
    uint32_t threads;
    uint32_t coding; /* what its WELCOME asked for: its DATA is raw or coded so */
    double since, last_result;
    uint32_t frame_sent; /* last frame it got an UPDATE for (0: none) */
    uint32_t scene_held; /* the description it was sent last (Server.scene_id; 0: none) */
    SentAsset *sent; /* the assets it was sent, by hash (a new scene keeps what it shares) */
    uint32_t nsent, sent_cap;
    uint32_t awaiting; /* ... of which it has not said HAVE */
    Upload up;         /* ... of which these are on their way, slice by slice */
    uint64_t segments, pixels, duplicates;
    uint64_t frame_pixels, last_frame_pixels; /* this frame's, and the last finished one's (the panel) */
    uint64_t busy_us;
    MeasureClient mc;       /* its results' timing, for the segment overhead */
    int older_ok;           /* it holds the older frame's view (it had that frame's UPDATE) */
    int closing;
} Client;

/* The older of two frames in flight (pipelined frames): the current
 * frame's state, moved here when the next frame started before it was
 * finished. */
typedef struct {
    uint32_t id; /* 0: one frame in flight */
    Sched *sched;
    uint8_t *pixels;
    uint32_t fw, fh;
    int scale, still, converged;
    double t0;
    RenderSettings rs; /* its view's settings (a batch: its pixels are sums) */
    uint32_t bpp;      /* its pixels' bytes */
    uint32_t cap;      /* the bytes a pixel its buffer was made for */
    Camera cam;        /* its camera, and its description's and settings' numbers */
    uint64_t epoch;
    int placed;        /* its instances' placements: Server.placed[placed] */
} Older;

/* A frame's instances as its description placed them, for its history
 * (render/temporal.h follows a turning model's pixels by their moves). */
typedef struct {
    Instance *inst;
    uint32_t count, cap;
} Placed;

struct Server {
    ServerConfig cfg;
    Scene *scene;
    int listen_fd, port;
    char address[80]; /* as net_listen shows it */
    Client *clients[MAX_CLIENTS];
    uint32_t nclients;
    int next_id;
    Sched *sched;
    uint32_t frame;   /* current frame id; 0 before the first */
    int in_frame, paused, dirty;
    View view;          /* the frame's camera and settings, apart from the description */
    uint32_t scene_id;  /* the description's number, one up each time it changes */
    /* ... one up each time it changes but by the animation's turns: the
     * histories' epoch (a turning model leaves the rest of the picture
     * where it was, and its history with it) */
    uint32_t edit_id;
    Scene *next_scene;  /* server_set_scene: the description of the frames to come, */
    AssetSet *next_assets; /* its assets, sent ahead to every client (ahead.c) */
    double ahead_t;     /* when they were sent ahead (0: nothing was), */
    uint64_t ahead_bytes; /* how many bytes, */
    uint32_t ahead_frame; /* and the frame then */
    Camera last_camera; /* the camera of the frame before, and its description's number: */
    uint32_t last_scene_id;
    int still;          /* the current frame's are the same (refinement) */
    int still_step;     /* and how many frames they have been: 1 the first still one, 0 a moving one */
    int sharp_first;    /* the frame before the first still one was at a render scale (refine_step) */
    int converged;      /* the current frame has the still quality (or is still, without refinement) */
    int next_scale;     /* server_set_scale: the moving frames' render scale (quarter steps: upscale.h) */
    int scale;          /* the current frame's, and its size: */
    uint32_t fw, fh;
    uint8_t *shown;     /* a scaled frame scaled up to the full size, for the callback */
    uint16_t *upscale_scratch; /* upscale_smooth's, made at the first scaled frame */
    double *upscale_rgbe;      /* upscale_smooth_rgbe's, likewise */
    /* changes held for the next frame (server_set_camera, server_turn_instances) */
    Camera next_camera;
    int camera_pending;
    real turn_pending;
    RenderSettings next_settings; /* server_set_settings */
    int settings_pending;
    int still_pending; /* server_set_still: a new still quality */
    int next_width, next_height; /* server_set_size (0: none held) */
    uint32_t settings_id, last_settings_id; /* one up at each change of the view's settings */
    double frame_t0, last_frame_s; /* the current frame's start, the last finished frame's time */
    uint8_t *pixels; /* the frame, bpp bytes a pixel: RGB8, or RGBE (hdr), then with denoise its guide */
    uint32_t bpp;
    /* the current frame's settings and bytes a pixel (a path-traced still's
     * batch: its sums, render/progressive.h); the bytes a pixel the frames'
     * buffers (pixels, spare_pixels) are made for */
    RenderSettings frame_rs;
    uint32_t frame_bpp, frame_cap;
    Camera frame_cam;    /* the current frame's camera, and its description's and settings' numbers */
    uint64_t frame_epoch;
    /* the placements of the frames in flight (two at most): the current
     * frame's placed[frame_placed], the older's the other */
    Placed placed[2];
    int frame_placed;
    /* the batches of a path-traced still so far: their sums, the pixels
     * they make (bpp), and the last batch added */
    real *acc_sums;
    uint8_t *acc_px;
    int acc_batch;
    Pool *acc_pool; /* ... added on these threads (NULL: the loop's alone) */
    uint32_t cbpp;   /* bytes of a pixel's colour, as shown */
    /* settings denoise (fixed for the server's life, as bpp): each finished
     * frame is filtered on the stage's thread, and shown once filtered; or
     * a Whitted view's moving frames added up there (settings guides), the
     * stage without its filter, made at the first (history_stage) */
    DenoiseStage *stage;
    int filters;        /* the stage filters (settings denoise) */
    int history_failed; /* a Whitted view's history could not be made: none */
    int raw_view;     /* denoised frames shown raw (server_set_denoise_shown) */
    uint8_t *stripped; /* ... a frame's colours without their guides */
    AssetSet *assets; /* models then textures of the scene */
    Sink scene_blob;  /* the serialised description (number scene_id) */
    Sink blob;        /* the current frame's view, and behind it scene_blob once a client lacks it */
    uint32_t view_len;
    int blob_has_scene;
    /* finished clients' statistics, for the summary */
    uint64_t gone_segments, gone_pixels, gone_bytes;
    uint32_t gone_clients; /* clients that left, or were dropped */
    int auto_segment;
    Measure m; /* for the summary line and the automatic segment size */
    PixCodec *codec; /* decodes coded DATA (the loop's one thread) */
    /* pipelined frames */
    SchedConfig sched_cfg; /* what a frame's scheduler is made with */
    Older older;
    Sched *spare_sched;    /* a frame's scheduler and pixels between frames */
    uint8_t *spare_pixels;
    FrameNextFn next_fn;
    void *next_ctx;
    FrameLinesFn lines_fn; /* server_on_lines, and a batch's pixels shown before it is whole */
    void *lines_ctx;
    uint8_t *peek_px;
    int shown_still, shown_scale, shown_converged, shown_samples; /* the frame shown last */
    uint32_t frames_dropped;      /* older frames nobody left could finish */
    uint32_t frames_ahead;        /* frames started before the one before was finished */
    uint32_t frames_given_way;    /* still frames dropped for a change (a move, a setting, an edit) */
};

/* ahead.c: a new scene's assets sent ahead of its frames */
void ahead_send_now(Server *s, Client *c);
void ahead_joined(Server *s, Client *c);
int ahead_pump(Server *s);
int ahead_ready(const Server *s);
void ahead_swap(Server *s);
void ahead_on_have(Server *s, Client *c);
void server_drop(Server *s, Client *c, const char *reason);
void server_send_or_drop(Server *s, Client *c, const MsgOut *m);

/* server.c, for frames.c */
int server_temporal_frames(const Server *s, const RenderSettings *rs);
SchedStats server_stats_all(const Server *s);
void server_apply_pending(Server *s);
void server_send_update(Server *s, Client *c);
DenoiseStage *server_stage_make(const Server *s, int width, int height, int filter, int temporal, Err *err);
uint64_t server_bytes(const Server *s);

/* frames.c, for the loop: the next frame started (0, or -1 with err
 * set), the frame after it started ahead where it may be (1: started),
 * and the frames that are whole shown in order (done called for each) */
int frames_start(Server *s, Err *err);
int frames_start_ahead(Server *s, Err *err);
void frames_finish(Server *s, FrameDoneFn done, void *ctx);

#endif

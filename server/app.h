/* app.h - what lanray-server's main loop holds: the server, the window
 * or the frames' folder, the scene shown and the one being read, the
 * pace, and what the summary counts.  Shared by main.c (the loop and the
 * frames) and livescene.c (the scene replaced while it runs). */
#ifndef LANRAY_SERVER_APP_H
#define LANRAY_SERVER_APP_H

#include <stdint.h>

#include "display.h"
#include "framerate.h"
#include "framewriter.h"
#include "net/mdns.h"
#include "pace.h"
#include "scene/camera_path.h"
#include "sceneload.h"
#include "server.h"
#include "watch.h"
#include "window.h"

typedef struct {
    const char *out_dir; /* NULL: frames are discarded (benchmarks) */
    Display *display;
    Server *server;
    Scene *scene;
    int width, height; /* the frames' (in a window, they follow its size) */
    int asked_w, asked_h; /* the size the scene (or the command line) asked last */
    uint8_t *view; /* settings hdr: the RGBE frame as sRGB codes for the window */
    uint32_t frames_done, frames_wanted;
    double last_title;
    const char *name; /* the scene's file name, for the title (NULL: the built-in scene): --scene's, or */
    char shown_name[256]; /* ... a dropped file's, once its scene is shown */
    const char *opening_name; /* a dropped file read, its scene not taken yet (its assets on their way), or NULL */
    const char *scene_path; /* its path (NULL: the built-in scene): --scene's, or */
    char *dropped;          /* ... a file dropped on the window since, which it points to */
    FrameRate rate;   /* the window's frame rate */
    int screenshot;
    uint8_t *shown;       /* the frame the window shows (P saves it), */
    uint32_t shown_frame; /* and its number */
    const char *progname;
    /* --verify: every frame compared with a reference image */
    const char *verify_path;
    uint8_t *verify;
    uint64_t wrong_frames, wrong_pixels;
    uint64_t write_failures;
    FrameWriter *writer;   /* headless: the frames written on a thread of their own (NULL: here) */
    /* --path: the camera flies it; the frames from the first to the one at its end */
    CameraPath path;
    uint32_t path_final;   /* the frame that shows the path's end (0: not set yet) */
    double path_t0, path_t1; /* when the first and that frame were shown */
    int refine;            /* --still-aa: still frames after the path's end, up to the converged one */
    double converged_t;    /* when it was shown, */
    uint32_t converged_frame; /* and its number */
    double still_t;        /* when the first still frame after the path's end (whole) was shown, 0: not yet */
    /* --target-fps: the render scale of the moving frames (quarter steps, upscale.h) */
    Pace pace;
    double last_frame_t;
    uint64_t scale_sum, scaled_frames;
    double longest;          /* the longest moving frame's time (a stutter), */
    uint32_t longest_frame;  /* and its number */
    int scales_before[2];    /* the last two moving frames' scales in a row (0: a still frame or none) */
    uint32_t scale_changes, scale_returns; /* a scale other than the frame before's; the one before that again */
    /* live edits: the scene file and its files watched, read again when one
     * changes; the new scene waits for the server to take it */
    Watch *watch;
    Scene *pending;
    double edit_t;         /* when the last event came (0: none waiting) */
    SceneLoad *loading;    /* a scene being read on a thread (livescene.c), or NULL; */
    int loading_drop;      /* ... a file dropped (else an edit), */
    double loading_t;      /* ... started then, */
    uint32_t loading_frames; /* ... when so many frames were done */
    char *queued;          /* the next to read once it is over (it is stale then), or NULL; */
    int queued_drop;       /* ... a file dropped (else an edit) */
    char edit_error[600];  /* the last read's error, shown in the title until a good read */
    Window win;            /* the window's controls and panel */
    int animate;           /* --rotate turns the instances (R toggles it) */
    double rotate, path_step, max_fps;
    MdnsAnnounce *mdns;    /* the farm announced on the LAN, or NULL */
} App;

#endif

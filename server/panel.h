/* panel.h - the text of the window's panel: what the server is doing and
 * the keys that change it, as lines (display.c draws them).  Pure text
 * from numbers, so that tests read it without a window. */
#ifndef LANRAY_PANEL_H
#define LANRAY_PANEL_H

#include <stdint.h>

#include "server.h"

#define PANEL_MAX_LINES 24
#define PANEL_LINE 100
#define PANEL_MAX_CLIENTS 8 /* more are summed up in one line */

typedef struct {
    double fps, frame_s;   /* frames a second shown (framerate.h), the last frame's time */
    double target_fps;     /* 0: none */
    int scale;             /* the last frame's render scale, in quarter steps (upscale.h; 4: every pixel) */
    int upscale_blocks;    /* frames at a scale shown in blocks, not smooth */
    int still;             /* the last frame was a still one */
    int converged;         /* ... the converged picture: no frame comes until something changes */
    int samples;           /* ... of this many samples a pixel (a path-traced still's so far) */
    int aa, adaptive;      /* the moving frames' sampling */
    int refine, still_aa, still_adaptive;
    int still_lights; /* the area lights' points a side the still frames refine up to; 0: their own */
    int light_adaptive, diffuse, shadows;
    int moving_lights; /* the area lights' points a side in moving frames (--moving-light-samples); 0: their own */
    int denoise;           /* 0: the server does not denoise; 1: frames shown denoised; 2: shown raw */
    int temporal;          /* the frames a moving pixel's history weighs (render/temporal.h; with denoise 0, a Whitted
                            * view's near the full size); 0: none */
    uint32_t segment_lines;
    int width, height;     /* the frames' size (in a window, its own unless --fixed-size) */
    const ServerClientInfo *clients;
    uint32_t nclients;
    const char *error;     /* the last edit's error, or NULL */
} PanelInfo;

/* The rate as the panel and the window's title say it: "15.0 fps", or
 * "converged" (the frame shown is the converged picture: no frame comes
 * until something changes). */
#define PANEL_RATE 24
void panel_rate(char out[PANEL_RATE], int converged, double fps);

/* The panel's lines into out (at most PANEL_MAX_LINES): how many. */
int panel_lines(const PanelInfo *p, char out[][PANEL_LINE]);

/* The target frame rates the T key steps through (0: none). */
double panel_next_target(double target, int up);

/* The still quality the N key steps to from (refine, aa, adaptive): off,
 * 2x2, adaptive 4x4, 4x4, off; a path-traced view's (path) goes on from
 * 4x4 to 16x16 and 32x32 (its still frames add up: 1024 samples a pixel
 * in 11 frames) before off. */
void panel_next_still(int path, int *refine, int *aa, int *adaptive);

#endif

/* window.h - what the window's keys and mouse do: the camera's moves
 * (navigate.c), the knobs of the frames to come (their settings, the still
 * quality, the frame-rate target) and the panel (panel.c) that shows them.
 * The knobs outlast a scene read again. */
#ifndef LANRAY_WINDOW_H
#define LANRAY_WINDOW_H

#include "display.h"
#include "navigate.h"
#include "pace.h"
#include "server.h"

/* Settings the keys changed, laid over every scene (-1: the scene's own). */
typedef struct {
    int shading, shadows;
} Knobs;

typedef struct {
    Display *display;
    Server *server;
    Pace *pace;
    Nav nav;
    Camera home;
    Knobs knobs;
    double target_fps;
    double last_poll, fps; /* fps: as the panel last said it */
    int panel_on, width, height; /* width, height: the frames' */
    int follow;                  /* the frames' size follows the window's (not --fixed-size) */
    int asked_w, asked_h;        /* ... the size last asked of the server */
    char dropped[4096];          /* a file dropped on the window, for the application to open ("": none) */
} Window;

void window_init(Window *w, Display *d, Server *s, Pace *pace, double target_fps, const Scene *scene, int width,
                 int height, int follow);
/* Another scene shown (a file dropped on the window): its camera is
 * Home's, and the moves' speed and C's framing follow its size. */
void window_new_scene(Window *w, const Scene *scene);
/* The knobs over a scene's settings (a scene read again). */
void window_knobs_apply(const Window *w, RenderSettings *rs);
/* The events since the last call, applied to the server for the next
 * frame (with follow, the window's size as the frames'): 1 where the user
 * asked to quit; *animate toggled by Space, *screenshot set by P, a file
 * dropped on the window in w->dropped. */
int window_poll(Window *w, int *animate, int *screenshot);
/* The panel again, where it is shown: fps over the last half second, and
 * the last edit's error (or NULL). */
void window_panel(Window *w, double fps, const char *error);

#endif

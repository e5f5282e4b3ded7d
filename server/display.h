/* display.h - the server's SDL2 window: shows frames and the panel, reads
 * keyboard and mouse. */
#ifndef LANRAY_DISPLAY_H
#define LANRAY_DISPLAY_H

#include <stdint.h>

#include "base/err.h"

typedef struct Display Display;

/* What the user did since the last poll. */
typedef struct {
    int quit, screenshot, reset, toggle_animation;
    double forward, right, up; /* keys held: -1, 0 or 1 */
    int fast;                  /* Shift held: move faster */
    double turn;               /* arrow keys held: -1..1 (left +) */
    double yaw, pitch;         /* degrees, from the mouse: a left drag looks round */
    double orbit_yaw, orbit_pitch; /* ... a right or middle drag orbits (navigate.h nav_orbit) */
    double pan_x, pan_y;           /* ... with Shift, pans: pixels (nav_pan) */
    double zoom;               /* zoom steps (+ in, - out) */
    /* the knobs: */
    int print_view; /* K: the view as a scene's camera line */
    char dropped[4096]; /* a file dropped on the window ("": none; of several, the last) */
    int toggle_panel, frame_all, target_up, target_down, next_still, toggle_lights, toggle_shading,
        toggle_shadows, toggle_upscale, toggle_denoise;
} DisplayInput;

/* Whether a display is there to open a window on. */
int display_available(void);
Display *display_open(int width, int height, Err *err);
void display_close(Display *d);
/* Shows a w x h frame (and the panel over it, where shown), drawn as
 * large as the window fits. */
void display_show(Display *d, const uint8_t *rgb, int w, int h);
/* Shows pixels [first, first + count) of the next frame (RGB8) over the
 * frame shown: a still frame refining as its segments come.  The screen
 * takes them at most ten times a second; display_flush, called
 * from the event loop, puts the rest there. */
void display_lines(Display *d, uint32_t first, uint32_t count, const uint8_t *rgb);
void display_flush(Display *d);
/* The panel's lines, drawn over the frame shown from now on (n = 0: no
 * panel); 0, or -1 with the reason where the window has no font. */
int display_panel(Display *d, char (*lines)[100], int n, Err *err);
void display_poll(Display *d, DisplayInput *in);
void display_title(Display *d, const char *title);
/* text on the clipboard, to paste elsewhere; 0, or -1 where it could not be put. */
int display_clipboard(Display *d, const char *text);
/* The window made w x h (less where the screen is smaller, its shape
 * kept), where the window manager lets it. */
void display_set_size(Display *d, int w, int h);
/* The width in pixels the frame shown is drawn at (the window's, or less
 * where the window's shape is not the frame's). */
int display_drawn_width(Display *d);
/* The window's size in pixels (what a frame drawn 1:1 would fill). */
void display_output_size(Display *d, int *w, int *h);

#endif

/* display.h - the server's SDL2 window: shows frames, reads keyboard and mouse. */
#ifndef LANRAY_DISPLAY_H
#define LANRAY_DISPLAY_H

#include <stdint.h>

#include "base/err.h"

typedef struct Display Display;

/* What the user did since the last poll. */
typedef struct {
    int quit, screenshot, reset, toggle_animation;
    double forward, right, up; /* movement, in steps */
    double yaw, pitch;         /* degrees */
    double zoom;               /* zoom steps (+ in, - out) */
} DisplayInput;

/* Whether a display is there to open a window on. */
int display_available(void);
Display *display_open(int width, int height, Err *err);
void display_close(Display *d);
void display_show(Display *d, const uint8_t *rgb);
void display_poll(Display *d, DisplayInput *in);
void display_title(Display *d, const char *title);

#endif

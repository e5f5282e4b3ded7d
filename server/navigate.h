/* navigate.h - the window's camera controls, apart from SDL: moves at a
 * speed scaled to the scene, reached and left smoothly, turns at a rate a
 * second, and the view that frames the whole scene.  Pure logic on a
 * Camera, so that tests drive it without a window. */
#ifndef LANRAY_NAVIGATE_H
#define LANRAY_NAVIGATE_H

#include "geom/camera.h"

typedef struct {
    vec3 vel;   /* metres a second along the camera's right, the world's up, the camera's forward */
    real speed; /* top speed: the scene's radius in NAV_CROSS_S seconds */
    vec3 centre;
    real radius; /* the scene's bounding sphere (scene_bounds), or a unit one */
    /* the last orbit's point and distance, and the camera it left: the
     * next orbit from that camera turns about the same point */
    vec3 pivot;
    real pivot_d;
    Camera orbited;
    int orbiting;
} Nav;

/* Seconds to cross the scene's radius at top speed, and the time constant
 * of the speed's approach to what the keys ask (a quarter of a second: no
 * jolt at a key's press or release). */
#define NAV_CROSS_S 1.5
#define NAV_EASE_S 0.15
/* Degrees a second that the arrow keys turn. */
#define NAV_TURN_DEG_S 90.0

void nav_init(Nav *n, vec3 centre, real radius);
/* Moves c over dt seconds while keys ask for `want` (each of right, up,
 * forward in -1..1; fast: three times the speed): 1 where the camera
 * moved.  The speed eases towards the keys' and stops below a thousandth
 * of the top speed. */
int nav_move(Nav *n, Camera *c, vec3 want, int fast, double dt);
/* Orbits c by yaw and pitch degrees about the point straight ahead at
 * the scene's depth (the view axis's point nearest the scene's centre; a
 * radius ahead where the centre is behind or near): what is in the
 * middle of the view stays there and the camera swings round it at its
 * distance, as a model viewer's drag does.  A camera the last orbit left
 * turns about that orbit's point again, so that a drag's steps make one
 * orbit however the mouse's moves came in.  Pitch stops at +-89 degrees
 * (the orbit with it). */
void nav_orbit(Nav *n, Camera *c, real yaw, real pitch);
/* Pans c by dx, dy pixels of a view `width` pixels wide (a Shift drag):
 * the camera slides along its right and up so that what lies at the
 * orbit's depth (nav_orbit's point) follows the pointer; an orthographic
 * view by its own width. */
void nav_pan(const Nav *n, Camera *c, double dx, double dy, int width);
/* The camera turned to see the whole bounding sphere from where it looks,
 * with a margin, at a frame of width x height; its direction kept. */
void nav_frame_all(const Nav *n, Camera *c, int width, int height);

#endif

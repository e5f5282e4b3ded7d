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
/* The camera turned to see the whole bounding sphere from where it looks,
 * with a margin, at a frame of width x height; its direction kept. */
void nav_frame_all(const Nav *n, Camera *c, int width, int height);

#endif

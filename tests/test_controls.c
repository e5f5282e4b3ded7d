/* test_controls.c - the window's controls apart from SDL: moves at a speed
 * the scene's size sets, eased in and out (server/navigate.c), the view
 * that frames the whole scene, the scene's bounds it frames (scene_bounds),
 * and the panel's text (server/panel.c): its numbers, its clients, the
 * target's steps. */
#include "helpers.h"

#include <math.h>

#include "navigate.h"
#include "panel.h"
#include "upscale.h"
#include "scene/scene_default.h"

/* Where the camera is after `seconds` of the forward key, in steps of dt. */
static real travel(real radius, double seconds, double dt)
{
    Nav n;
    nav_init(&n, v3_splat(0), radius);
    Camera c = camera_from_angles(v3(0, 0, 0), 0, 0, 0, 1);
    for (double t = 0; t < seconds - 1e-9; t += dt)
        nav_move(&n, &c, v3(0, 0, 1), 0, dt);
    return v3_len(c.pos);
}

static void speed_follows_the_scene_and_eases(void **state)
{
    (void)state;
    /* a scene ten times the size: ten times the way in the same time */
    real small = travel(1, 2, 1.0 / 60), big = travel(10, 2, 1.0 / 60);
    assert_true(fabs(big / small - R(10)) < R(1e-2));
    /* top speed: the radius in NAV_CROSS_S seconds; 2 s of the key gets
     * near it (less the ease-in), never past */
    assert_true(small > R(0.8) * R(2) / (real)NAV_CROSS_S && small < R(2) / (real)NAV_CROSS_S);
    /* no jolt: the first sixtieth of a second moves at under a fifth of top speed */
    real first = travel(1, 1.0 / 60, 1.0 / 60);
    assert_true(first < R(0.2) / (real)NAV_CROSS_S / R(60));
    assert_true(first > R(0));
    /* the same way at 10 or 60 steps a second, within a tenth */
    real coarse = travel(1, 2, 0.1);
    assert_true(fabs(coarse / small - R(1)) < R(0.1));
    /* let go: it glides to a stop and then reports no move */
    Nav n;
    nav_init(&n, v3_splat(0), 1);
    Camera c = camera_from_angles(v3(0, 0, 0), 0, 0, 0, 1);
    for (int i = 0; i < 60; i++)
        nav_move(&n, &c, v3(1, 0, 0), 0, 1.0 / 60);
    const vec3 at = c.pos;
    assert_int_equal(nav_move(&n, &c, v3_splat(0), 0, 1.0 / 60), 1);
    assert_true(c.pos.x > at.x); /* still gliding right */
    int moved = 1;
    for (int i = 0; i < 600 && moved; i++)
        moved = nav_move(&n, &c, v3_splat(0), 0, 1.0 / 60);
    assert_int_equal(moved, 0);
    /* Shift: three times as fast */
    nav_init(&n, v3_splat(0), 1);
    c = camera_from_angles(v3(0, 0, 0), 0, 0, 0, 1);
    for (int i = 0; i < 120; i++)
        nav_move(&n, &c, v3(0, 0, 1), 1, 1.0 / 60);
    assert_true(fabs(v3_len(c.pos) / small - R(3)) < R(0.01));
}

static void frame_all_sees_the_whole_scene(void **state)
{
    (void)state;
    Scene *s;
    Err err;
    BvhOptions bo = bvh_options_default(BVH_SAH);
    assert_int_equal(scene_default(&s, &bo, &err), 0);
    vec3 centre;
    real radius;
    assert_int_equal(scene_bounds(s, &centre, &radius), 0);
    /* every sphere of the default scene lies in the bounding sphere */
    for (uint32_t i = 0; i < s->sphere_count; i++)
        assert_true(v3_len(v3_sub(s->spheres[i].centre, centre)) + s->spheres[i].radius <= radius * R(1.0001));
    Nav n;
    nav_init(&n, centre, radius);
    Camera c = camera_from_angles(v3(5, 1, 20), 30, -10, 0, R(1.5));
    nav_frame_all(&n, &c, 1024, 768);
    vec3 r, u, f;
    camera_basis(&c, &r, &u, &f);
    const vec3 to = v3_sub(centre, c.pos);
    /* the centre straight ahead, the direction kept (yaw and pitch as they were) */
    assert_true(v3_dot(v3_norm(to), f) > R(0.9999));
    assert_true(c.yaw == R(30) && c.pitch == R(-10));
    /* the sphere inside the narrower (vertical) half-angle, with its margin */
    const real half = atan(R(0.75) / c.zoom);
    assert_true(asin(radius / v3_len(to)) < half);
    assert_true(asin(radius / v3_len(to)) > R(0.8) * half);
    scene_destroy(s);
    /* a scene of planes alone has no bounds to frame */
    Scene *p = scene_create();
    assert_non_null(p);
    assert_int_equal(scene_bounds(p, &centre, &radius), -1);
    scene_destroy(p);
}

/* Whether c looks straight at p from dist away (within tol). */
static int aims_at(const Camera *c, vec3 p, real dist, real tol)
{
    vec3 r, u, f;
    camera_basis(c, &r, &u, &f);
    const vec3 to = v3_sub(p, c->pos);
    return fabs(v3_len(to) - dist) < tol && v3_dot(v3_norm(to), f) > R(0.99999);
}

/* A scene of radius 2 round (1, 2, -3) and a camera 10 in front of it
 * (+z), looking at it, of that zoom. */
static const vec3 *nav_before(Nav *n, Camera *c, real zoom)
{
    static const vec3 centre = {.e = {1, 2, -3}};
    nav_init(n, centre, 2);
    *c = camera_from_angles(v3_add(centre, v3(0, 0, 10)), 0, 0, 0, zoom);
    return &centre;
}

/* The orbit: what is in the middle of the view stays there, at the
 * distance it was, the camera swung round it by the angles asked. */
static void orbit_swings_round_the_middle(void **state)
{
    (void)state;
    Nav n;
    Camera c;
    const vec3 centre = *nav_before(&n, &c, 1);
    /* looking at the centre from 10 away: the centre stays ahead, 10 away */
    nav_orbit(&n, &c, 30, 20);
    assert_true(aims_at(&c, centre, 10, R(1e-4)));
    assert_true(c.yaw == R(30) && c.pitch == R(20));
    /* where it went: 10 x (sin 30 cos 20, -sin 20, cos 30 cos 20) from the
     * centre (yaw to the left swings it to the right; pitched up, it looks
     * up at the centre from below) */
    const real deg = REAL_PI / R(180);
    const vec3 want = v3_scale(v3(sin(30 * deg) * cos(20 * deg), -sin(20 * deg), cos(30 * deg) * cos(20 * deg)), 10);
    assert_true(v3_len(v3_sub(v3_sub(c.pos, centre), want)) < R(1e-4));
    /* the pitch stops at 89 degrees and the orbit with it */
    nav_orbit(&n, &c, 0, 200);
    assert_true(c.pitch == R(89) && aims_at(&c, centre, 10, R(1e-3)));
    /* off-centre: the point of the view axis at the centre's depth stays put */
    c = camera_from_angles(v3(centre.x + 3, centre.y, centre.z + 8), 0, 0, 0, 1);
    nav_orbit(&n, &c, -45, 0);
    assert_true(aims_at(&c, v3(centre.x + 3, centre.y, centre.z), 8, R(1e-4)));
    /* a drag's steps make one orbit: 10 then 20 degrees off-centre is 30
     * at once (the point found again from the turned camera would be
     * another: the view axis's point nearest the centre has moved) */
    Camera one = camera_from_angles(v3(centre.x + 3, centre.y + 1, centre.z + 8), 0, 0, 0, 1), two = one;
    Nav n1, n2;
    nav_init(&n1, centre, 2);
    nav_init(&n2, centre, 2);
    nav_orbit(&n1, &one, 30, -12);
    nav_orbit(&n2, &two, 10, -4);
    nav_orbit(&n2, &two, 20, -8);
    assert_true(v3_len(v3_sub(one.pos, two.pos)) < R(1e-4) && one.yaw == two.yaw && one.pitch == two.pitch);
    /* ... and a camera moved since starts a new one about its own middle */
    two.pos.x += 1;
    const vec3 moved = two.pos;
    nav_orbit(&n2, &two, 0, 0);
    assert_true(v3_len(v3_sub(two.pos, moved)) < R(1e-4));
    /* the centre behind the camera: it swings round a point a radius ahead */
    c = camera_from_angles(v3(centre.x, centre.y, centre.z - 5), 0, 0, 0, 1);
    nav_orbit(&n, &c, 90, 0);
    assert_true(aims_at(&c, v3(centre.x, centre.y, centre.z - 7), 2, R(1e-4)));
}

/* A pan: the point at the orbit's depth follows the pointer, pixel for
 * pixel, the camera's angles kept. */
static void pan_follows_the_pointer(void **state)
{
    (void)state;
    Nav n;
    Camera c;
    /* 10 ahead, zoom 2 (the view plane 2 wide at 2: 10 wide at the
     * centre), 400 pixels wide: 1/40 a pixel */
    const vec3 centre = *nav_before(&n, &c, 2);
    nav_pan(&n, &c, 40, -20, 400);
    const vec3 want = v3_add(centre, v3(-1, -0.5, 10)); /* dragged right and up: the camera goes left and down */
    assert_true(v3_len(v3_sub(c.pos, want)) < R(1e-5));
    assert_true(c.yaw == R(0) && c.pitch == R(0) && c.zoom == R(2));
    /* turned 90 degrees (looking along -x), its right is -z */
    c = camera_from_angles(v3_add(centre, v3(10, 0, 0)), 90, 0, 0, 2);
    nav_pan(&n, &c, 40, 0, 400);
    assert_true(v3_len(v3_sub(c.pos, v3_add(centre, v3(10, 0, 1)))) < R(1e-5));
    /* an orthographic view 8 wide: 8/400 a pixel, whatever the depth */
    c = camera_from_angles(v3_add(centre, v3(0, 0, 10)), 0, 0, 0, 2);
    c.kind = CAMERA_ORTHO, c.size = 8;
    nav_pan(&n, &c, 50, 0, 400);
    assert_true(v3_len(v3_sub(c.pos, v3_add(centre, v3(-1, 0, 10)))) < R(1e-5));
}

/* Whether a line of the panel holds `text`. */
static int has(char lines[][PANEL_LINE], int n, const char *text)
{
    for (int i = 0; i < n; i++)
        if (strstr(lines[i], text))
            return 1;
    return 0;
}

static void panel_says_what_runs(void **state)
{
    (void)state;
    ServerClientInfo clients[10];
    for (int i = 0; i < 10; i++) {
        clients[i] = (ServerClientInfo){.id = i + 1, .threads = 2, .share = i < 2 ? 0.3 : 0.05, .lines_per_s = 1000 + i};
        snprintf(clients[i].addr, sizeof clients[i].addr, "10.0.0.%d:4000", i + 1);
    }
    PanelInfo p = {.fps = 14.64, .frame_s = 0.0683, .target_fps = 15, .scale = 4 * UPSCALE_ONE, .aa = 1, .refine = 1,
                   .still_aa = 4, .still_adaptive = 1, .light_adaptive = 1, .shadows = 1, .segment_lines = 8,
                   .width = 390, .height = 150, .clients = clients, .nclients = 2};
    char lines[PANEL_MAX_LINES][PANEL_LINE];
    int n = panel_lines(&p, lines);
    assert_true(has(lines, n, "14.6 fps  latency 68.3 ms  moving"));
    assert_true(has(lines, n, "target 15 fps") && has(lines, n, "render scale 1/4 smooth [U]"));
    assert_true(has(lines, n, "moving 1x1, still adaptive 4x4"));
    assert_true(has(lines, n, "moving lights adaptive") && has(lines, n, "phong") && has(lines, n, "shadows on"));
    assert_true(has(lines, n, "moving lights adaptive [L]"));
    /* a still picture refining, then the converged one: no rate, nothing comes */
    p.still = 1, p.samples = 16, p.fps = 1.49, p.frame_s = 0.6716;
    n = panel_lines(&p, lines);
    assert_true(has(lines, n, "1.5 fps  671.6 ms  still, 16 samples a pixel"));
    p.converged = 1;
    n = panel_lines(&p, lines);
    assert_true(has(lines, n, "converged  671.6 ms  still, 16 samples a pixel") && !has(lines, n, "fps  "));
    p.still = 0, p.converged = 0, p.samples = 0, p.fps = 14.64, p.frame_s = 0.0683;
    p.moving_lights = 2; /* --moving-light-samples */
    n = panel_lines(&p, lines);
    assert_true(has(lines, n, "moving lights adaptive 2x2 [L]  phong [M]"));
    p.moving_lights = 0;
    assert_true(has(lines, n, "frames 390x150, segments of 8 lines") && has(lines, n, "2 clients"));
    assert_true(has(lines, n, "10.0.0.2:4000") && has(lines, n, "1001 lines/s") && has(lines, n, "30.0%"));
    assert_false(has(lines, n, "error"));
    /* ten clients: eight named, the other two summed */
    p.nclients = 10;
    p.error = "e.scene:9: unknown directive 'sphre'";
    p.target_fps = 0;
    n = panel_lines(&p, lines);
    assert_true(n <= PANEL_MAX_LINES);
    assert_true(has(lines, n, "10.0.0.8:4000") && !has(lines, n, "10.0.0.9:4000"));
    assert_true(has(lines, n, "2 more") && has(lines, n, "10.0%"));
    assert_true(has(lines, n, "error: e.scene:9") && has(lines, n, "target none"));
    p.upscale_blocks = 1;
    n = panel_lines(&p, lines);
    assert_true(has(lines, n, "render scale 1/4 blocks [U]") && !has(lines, n, "smooth"));
    p.scale = 10; /* quarter steps: 2.5 */
    n = panel_lines(&p, lines);
    assert_true(has(lines, n, "render scale 1/2.5 blocks [U]"));
    assert_false(has(lines, n, "lights to"));
    /* still frames that refine the area lights' points say how far */
    p.still_lights = 12;
    n = panel_lines(&p, lines);
    assert_true(has(lines, n, "moving 1x1, still adaptive 4x4, lights to 12x12"));
    /* a denoising server says how its frames are shown, on a line of its own */
    assert_false(has(lines, n, "[X]") || has(lines, n, "added up"));
    p.temporal = 2; /* a Whitted view's history */
    n = panel_lines(&p, lines);
    assert_true(has(lines, n, "moving frames near the full size added up (2)"));
    p.temporal = 0;
    p.denoise = 2;
    n = panel_lines(&p, lines);
    assert_true(has(lines, n, "frames shown raw [X]"));
    p.denoise = 1;
    n = panel_lines(&p, lines);
    assert_true(has(lines, n, "frames shown denoised [X]") && !has(lines, n, "added up"));
    p.temporal = 8; /* ... and that its moving frames are added up */
    n = panel_lines(&p, lines);
    assert_true(has(lines, n, "frames shown denoised [X], moving ones added up"));
    assert_false(has(lines, n, "near the full size"));
    assert_true(has(lines, n, "shadows on [H]") && !has(lines, n, "[H]  "));
    /* a still frame says its samples (a path-traced one's so far) */
    assert_true(has(lines, n, "moving") && !has(lines, n, "samples a pixel"));
    p.still = 1, p.samples = 64;
    n = panel_lines(&p, lines);
    assert_true(has(lines, n, "still, 64 samples a pixel"));
}

static void still_steps(void **state)
{
    (void)state;
    for (int path = 0; path < 2; path++) {
        int refine = 0, aa = 1, adaptive = 0;
        char seen[64] = "";
        for (int k = 0; k < 7; k++) {
            panel_next_still(path, &refine, &aa, &adaptive);
            char step[16];
            snprintf(step, sizeof step, "%s%d ", !refine ? "off" : adaptive ? "a" : "", refine ? aa : 0);
            strcat(seen, step);
            if (!refine)
                break;
        }
        assert_string_equal(seen, path ? "2 a4 4 16 32 off0 " : "2 a4 4 off0 ");
    }
    /* a quality given on the command line steps on from where it is */
    int refine = 1, aa = 8, adaptive = 0;
    panel_next_still(1, &refine, &aa, &adaptive);
    assert_true(refine && aa == 16 && !adaptive);
    panel_next_still(0, &refine, &aa, &adaptive);
    assert_false(refine);
}

static void target_steps(void **state)
{
    (void)state;
    assert_true(panel_next_target(0, 1) == 5);
    assert_true(panel_next_target(5, 1) == 10);
    assert_true(panel_next_target(15, 1) == 24);
    assert_true(panel_next_target(15, 0) == 10);
    assert_true(panel_next_target(12, 0) == 10); /* between steps: to the one below */
    assert_true(panel_next_target(12, 1) == 15);
    assert_true(panel_next_target(60, 1) == 60);
    assert_true(panel_next_target(5, 0) == 0);
    assert_true(panel_next_target(0, 0) == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(speed_follows_the_scene_and_eases),
        cmocka_unit_test(frame_all_sees_the_whole_scene),
        cmocka_unit_test(orbit_swings_round_the_middle),
        cmocka_unit_test(pan_follows_the_pointer),
        cmocka_unit_test(panel_says_what_runs),
        cmocka_unit_test(target_steps),
        cmocka_unit_test(still_steps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

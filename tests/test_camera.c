/* test_camera.c - both camera forms (angles and look-at), the per-frame ray
 * constants, and the orthographic and fisheye cameras' rays. */
#include "helpers.h"

#include "geom/camera.h"

static const real EPS = R(1e-5);

static void assert_vec_near(vec3 a, vec3 b, real eps)
{
    assert_float_equal(a.x, b.x, eps);
    assert_float_equal(a.y, b.y, eps);
    assert_float_equal(a.z, b.z, eps);
}

static void zero_angles_look_down_minus_z(void **state)
{
    (void)state;
    Camera c = camera_from_angles(v3(0, 0, 0), 0, 0, 0, 1);
    vec3 r, u, f;
    camera_basis(&c, &r, &u, &f);
    assert_vec_near(f, v3(0, 0, -1), EPS);
    assert_vec_near(r, v3(1, 0, 0), EPS);
    assert_vec_near(u, v3(0, 1, 0), EPS);
    /* yaw 90 turns left to -x; pitch 90 looks straight up */
    c = camera_from_angles(v3(0, 0, 0), 90, 0, 0, 1);
    camera_basis(&c, &r, &u, &f);
    assert_vec_near(f, v3(-1, 0, 0), EPS);
    assert_vec_near(r, v3(0, 0, -1), EPS);
    c = camera_from_angles(v3(0, 0, 0), 0, 90, 0, 1);
    camera_basis(&c, &r, &u, &f);
    assert_vec_near(f, v3(0, 1, 0), EPS);
    assert_vec_near(u, v3(0, 0, 1), EPS);
    /* roll 90: the right vector turns into the old up vector */
    c = camera_from_angles(v3(0, 0, 0), 0, 0, 90, 1);
    camera_basis(&c, &r, &u, &f);
    assert_vec_near(r, v3(0, 1, 0), EPS);
    assert_vec_near(u, v3(-1, 0, 0), EPS);
}

static void look_at_matches_angles(void **state)
{
    (void)state;
    Rng rng = {99};
    for (int i = 0; i < 1000; i++) {
        vec3 pos = rng_vec(&rng, -50, 50), target = rng_vec(&rng, -50, 50);
        real roll = rng_real(&rng, -180, 180);
        Camera c;
        assert_int_equal(camera_look_at(&c, pos, target, roll, 2), 0);
        vec3 r, u, f;
        camera_basis(&c, &r, &u, &f);
        assert_vec_near(f, v3_norm(v3_sub(target, pos)), R(1e-4));
        /* the same angles given directly give the same basis */
        Camera d = camera_from_angles(pos, c.yaw, c.pitch, c.roll, 2);
        vec3 r2, u2, f2;
        camera_basis(&d, &r2, &u2, &f2);
        assert_vec_near(r, r2, EPS);
        assert_vec_near(u, u2, EPS);
        /* orthonormal, right-handed: right x up = -forward */
        assert_float_equal(v3_len(r), 1, R(1e-4));
        assert_float_equal(v3_len(u), 1, R(1e-4));
        assert_float_equal(v3_dot(r, u), 0, R(1e-4));
        assert_float_equal(v3_dot(r, f), 0, R(1e-4));
        assert_vec_near(v3_cross(r, u), v3_neg(f), R(1e-4));
    }
    Camera c;
    assert_int_equal(camera_look_at(&c, v3(1, 2, 3), v3(1, 2, 3), 0, 1), -1);
    /* looking straight down is not degenerate */
    assert_int_equal(camera_look_at(&c, v3(0, 10, 0), v3(0, 0, 0), 0, 1), 0);
    vec3 r, u, f;
    camera_basis(&c, &r, &u, &f);
    assert_vec_near(f, v3(0, -1, 0), EPS);
    assert_float_equal(v3_len(r), 1, EPS);
}

static void frame_rays_span_the_field_of_view(void **state)
{
    (void)state;
    Camera c = camera_from_angles(v3(1, 2, 3), 30, -10, 5, camera_zoom_for_fov(90));
    vec3 r, u, f;
    camera_basis(&c, &r, &u, &f);
    CameraFrame fr = camera_frame(&c, 640, 480);
    /* centre of the image: straight ahead */
    vec3 d = v3_norm(camera_dir(&fr, 320, 240));
    assert_vec_near(d, f, EPS);
    /* left and right edges at the middle row: 45 degrees off the axis for fov 90 */
    vec3 left = v3_norm(camera_dir(&fr, 0, 240)), right = v3_norm(camera_dir(&fr, 640, 240));
    assert_float_equal(v3_dot(left, f), cos(REAL_PI / 4), EPS);
    assert_float_equal(v3_dot(right, f), cos(REAL_PI / 4), EPS);
    assert_true(v3_dot(left, r) < 0 && v3_dot(right, r) > 0);
    /* top row is up, bottom row is down; square pixels: vertical extent is 480/640 of horizontal */
    vec3 top = camera_dir(&fr, 320, 0), bottom = camera_dir(&fr, 320, 480);
    assert_true(v3_dot(top, u) > 0 && v3_dot(bottom, u) < 0);
    assert_float_equal((v3_dot(top, u) / v3_dot(camera_dir(&fr, 640, 240), r)), R(480.0 / 640.0), EPS);
    /* 1x1 frames work: the single pixel centre looks straight ahead */
    CameraFrame one = camera_frame(&c, 1, 1);
    assert_vec_near(v3_norm(camera_dir(&one, R(0.5), R(0.5))), f, EPS);
}

/* Parallel rays along the view direction, from a rectangle `size` wide
 * centred on the camera's position, one pixel apart by size / width. */
static void orthographic_rays_are_parallel_and_evenly_spaced(void **state)
{
    (void)state;
    Camera c = camera_from_angles(v3(1, 2, 3), 30, -10, 5, 1);
    c.kind = CAMERA_ORTHO;
    c.size = 8;
    vec3 r, u, f;
    camera_basis(&c, &r, &u, &f);
    CameraFrame fr = camera_frame(&c, 400, 300);
    vec3 o, d, o2, d2;
    assert_true(camera_ray(&fr, 200, 150, &o, &d));
    assert_vec_near(o, c.pos, EPS);
    assert_vec_near(d, f, EPS);
    for (int i = 0; i < 50; i++) {
        real x = (real)(i * 8), y = (real)(i * 6);
        assert_true(camera_ray(&fr, x, y, &o, &d) && camera_ray(&fr, x + 1, y + 1, &o2, &d2));
        assert_vec_near(d, f, 0);
        assert_vec_near(d2, f, 0);
        /* one pixel right and one down: size / width along right, and down */
        assert_vec_near(v3_sub(o2, o), v3_scale(v3_sub(r, u), R(8.0 / 400.0)), EPS);
    }
    /* the corners: half the width to each side, half the height (square pixels) up and down */
    assert_true(camera_ray(&fr, 0, 0, &o, &d));
    assert_vec_near(o, v3_add(v3_sub(c.pos, v3_scale(r, 4)), v3_scale(u, 3)), EPS);
}

/* Equidistant: the angle from the view direction is proportional to the
 * distance from the image centre, fov / 2 at the left and right edges;
 * outside that circle there is no ray. */
static void fisheye_angles_grow_with_distance_from_the_centre(void **state)
{
    (void)state;
    Camera c = camera_from_angles(v3(0, 1, 0), -40, 20, 0, 1);
    c.kind = CAMERA_FISHEYE;
    vec3 r, u, f, o, d;
    camera_basis(&c, &r, &u, &f);
    const real fovs[] = {90, 180, 270, 360};
    for (int k = 0; k < 4; k++) {
        c.fov = fovs[k];
        CameraFrame fr = camera_frame(&c, 400, 400);
        assert_true(camera_ray(&fr, 200, 200, &o, &d));
        assert_vec_near(o, c.pos, 0);
        assert_vec_near(d, f, EPS);
        real half = fovs[k] * REAL_PI / 360;
        for (int i = 1; i <= 8; i++) {
            real px = (real)i * 25, ang = half * px / 200;
            /* along the row to the right, and up the column: turning towards right, and up */
            assert_true(camera_ray(&fr, 200 + px, 200, &o, &d));
            assert_float_equal(v3_dot(d, f), cos(ang), EPS);
            assert_float_equal(v3_dot(d, r), sin(ang), EPS);
            assert_true(camera_ray(&fr, 200, 200 - px, &o, &d));
            assert_float_equal(v3_dot(d, u), sin(ang), EPS);
        }
        /* the left edge, and the corner outside the circle */
        assert_true(camera_ray(&fr, 0, 200, &o, &d));
        assert_float_equal(v3_dot(d, f), cos(half), EPS);
        assert_true(v3_dot(d, r) < R(1e-5));
        assert_false(camera_ray(&fr, 0, 0, &o, &d));
    }
    /* 360 degrees: the edge of the circle looks straight back */
    c.fov = 360;
    CameraFrame full = camera_frame(&c, 400, 400);
    assert_true(camera_ray(&full, 400, 200, &o, &d));
    assert_vec_near(d, v3_neg(f), R(1e-4));
}

/* A thin lens: every ray of one image position, from any point of the
 * lens, passes through the same point at the focus distance (the pinhole
 * ray's point there), and the rays leave from within the aperture. */
static void thin_lens_focuses_at_the_focus_distance(void **state)
{
    (void)state;
    Camera c = camera_from_angles(v3(1, 2, 3), 25, -15, 10, camera_zoom_for_fov(60));
    c.aperture = R(0.4);
    c.focus = R(7.5);
    vec3 r, u, f;
    camera_basis(&c, &r, &u, &f);
    CameraFrame fr = camera_frame(&c, 320, 240);
    const real pos[4][2] = {{160, 120}, {0, 0}, {319.5, 17.25}, {40, 200}};
    for (int p = 0; p < 4; p++) {
        vec3 d0 = v3_norm(camera_dir(&fr, pos[p][0], pos[p][1]));
        vec3 want = v3_madd(c.pos, d0, c.focus / v3_dot(d0, f)); /* on the focal plane */
        for (int i = 0; i <= 4; i++)
            for (int j = 0; j <= 4; j++) {
                vec3 o, d;
                camera_lens_ray(&fr, pos[p][0], pos[p][1], (real)i / 4, (real)j / 4, &o, &d);
                vec3 off = v3_sub(o, c.pos);
                assert_true(v3_len(off) <= R(0.2) + EPS);   /* on the lens: within the aperture's radius */
                assert_float_equal(v3_dot(off, f), 0, EPS); /* in the camera's right-up plane */
                real t = v3_dot(v3_sub(want, o), f) / v3_dot(d, f);
                assert_vec_near(v3_madd(o, d, t), want, R(2e-5) * c.focus);
            }
    }
    /* points off the focal plane blur: two lens rays of one position part there */
    vec3 o1, d1, o2, d2;
    camera_lens_ray(&fr, 160, 120, 0, R(0.5), &o1, &d1);
    camera_lens_ray(&fr, 160, 120, 1, R(0.5), &o2, &d2);
    vec3 a = v3_madd(o1, d1, R(3)), b = v3_madd(o2, d2, R(3));
    assert_true(v3_len(v3_sub(a, b)) > R(0.1));
}

/* camera_project inverts camera_ray: the point at distance t along the
 * ray of image position (x, y) projects back to (x, y) and t, for every
 * kind of camera, near and far (1e-3 to 1e6 away, at coordinates of 1e5),
 * and points behind a camera or outside a fisheye's circle project
 * nowhere. */
static void projection_inverts_the_rays(void **state)
{
    (void)state;
    for (int kind = 0; kind < 3; kind++)
        for (int far = 0; far < 2; far++) {
            Camera c = camera_from_angles(far ? v3(1e5, -3e4, 2e5) : v3(1, 2, 3), 35, -20, 15, camera_zoom_for_fov(70));
            c.kind = (CameraKind)kind;
            c.size = R(4);
            c.fov = R(200);
            CameraFrame fr = camera_frame(&c, 320, 240);
            const real pos[5][2] = {{160, 120}, {0.5, 0.5}, {319.5, 17.25}, {40, 200}, {200, 60}};
            const real dists[4] = {R(1e-3), R(0.7), R(40), R(1e6)};
            for (int p = 0; p < 5; p++)
                for (int k = 0; k < 4; k++) {
                    vec3 o, d;
                    /* (a millimetre at 1e5 is below a float's step there, and at 1e6 so is
                     * an orthographic pixel's width, 1/80) */
                    if (!camera_ray(&fr, pos[p][0], pos[p][1], &o, &d) || (far && k == 0) ||
                        (kind == CAMERA_ORTHO && k == 3))
                        continue;
                    real x, y, t;
                    assert_true(camera_project(&fr, v3_madd(o, d, dists[k]), &x, &y, &t));
                    /* a relative error of the coordinates' size, spread by the lever to the point */
                    const real tol = R(2e-3) * (far ? R(1e5) / dists[k] + R(1) : R(1) + R(1) / dists[k]);
                    assert_float_equal(x, pos[p][0], tol);
                    assert_float_equal(y, pos[p][1], tol);
                    assert_float_equal(t, dists[k], R(1e-4) * dists[k] + (far ? R(0.05) : R(1e-5)));
                }
            vec3 r, u, f;
            camera_basis(&c, &r, &u, &f);
            real x, y, t;
            if (kind != CAMERA_FISHEYE) /* behind the camera (a fisheye of 200 degrees sees some of it) */
                assert_false(camera_project(&fr, v3_madd(c.pos, f, R(-5)), &x, &y, &t));
            else /* straight back: past the circle's 100 degrees */
                assert_false(camera_project(&fr, v3_madd(c.pos, f, R(-5)), &x, &y, &t));
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(zero_angles_look_down_minus_z),
        cmocka_unit_test(look_at_matches_angles),
        cmocka_unit_test(frame_rays_span_the_field_of_view),
        cmocka_unit_test(orthographic_rays_are_parallel_and_evenly_spaced),
        cmocka_unit_test(fisheye_angles_grow_with_distance_from_the_centre),
        cmocka_unit_test(thin_lens_focuses_at_the_focus_distance),
        cmocka_unit_test(projection_inverts_the_rays),
    };
    return cmocka_run_group_tests_name("camera", tests, NULL, NULL);
}

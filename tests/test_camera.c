/* test_camera.c - both camera forms (angles and look-at) and the per-frame ray constants. */
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(zero_angles_look_down_minus_z),
        cmocka_unit_test(look_at_matches_angles),
        cmocka_unit_test(frame_rays_span_the_field_of_view),
    };
    return cmocka_run_group_tests_name("camera", tests, NULL, NULL);
}

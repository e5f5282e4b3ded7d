/* test_optics.c - reflection, refraction and Fresnel against analytic
 * answers, a ray through a glass sphere to the point geometry predicts, and
 * mirrors and glass in whole renders (what shade_ray adds and what it does
 * not trace). */
#include "helpers.h"
#include "worlds.h"

#include <math.h>

#include "shading/optics.h"
#include "scene/shade.h"

#define N_GLASS R(1.5)
/* float: a few ulps of a unit quantity after a sqrt or two */
#define TOL (sizeof(real) == 4 ? 2e-6 : 1e-12)

static void assert_vec_near(vec3 a, vec3 b, double tol)
{
    for (int k = 0; k < 3; k++)
        if (fabs((double)a.e[k] - (double)b.e[k]) > tol)
            fail_msg("(%.9g %.9g %.9g) differs from (%.9g %.9g %.9g) by more than %g", (double)a.x, (double)a.y,
                     (double)a.z, (double)b.x, (double)b.y, (double)b.z, tol);
}

/* A unit direction in the x-y plane arriving at the surface y = 0 (normal
 * +y) at incidence angle a (radians). */
static vec3 arriving(double a) { return v3((real)sin(a), (real)-cos(a), 0); }

static void reflection_mirrors_about_the_normal(void **state)
{
    (void)state;
    vec3 n = v3(0, 1, 0);
    for (double a = 0; a < 1.55; a += 0.1) {
        vec3 r = optics_reflect(arriving(a), n);
        assert_vec_near(r, v3((real)sin(a), (real)cos(a), 0), TOL);
    }
    /* a tilted normal: the angle to it is kept and the three are coplanar */
    Rng rng = {7};
    for (int i = 0; i < 1000; i++) {
        vec3 m = v3_norm(rng_vec(&rng, -1, 1)), d = v3_norm(rng_vec(&rng, -1, 1));
        if (v3_dot(d, m) > 0)
            d = v3_neg(d);
        vec3 r = optics_reflect(d, m);
        assert_float_equal(v3_dot(r, m), -v3_dot(d, m), 1e-5);
        assert_float_equal(v3_len(r), 1, 1e-5);
        assert_float_equal(v3_dot(v3_cross(d, m), r), 0, 1e-5);
    }
}

static void refraction_follows_snell(void **state)
{
    (void)state;
    vec3 n = v3(0, 1, 0), t = v3_splat(0);
    /* normal incidence goes straight through */
    assert_true(optics_refract(v3(0, -1, 0), n, R(1) / N_GLASS, &t));
    assert_vec_near(t, v3(0, -1, 0), TOL);
    /* n1 sin i = n2 sin t, both ways, and the result is a unit vector below the surface */
    for (double a = 0.05; a < 1.55; a += 0.1) {
        double st = sin(a) / 1.5;
        assert_true(optics_refract(arriving(a), n, R(1) / N_GLASS, &t));
        assert_vec_near(t, v3((real)st, (real)-sqrt(1 - st * st), 0), 4 * TOL);
        double crit = asin(1 / 1.5);
        if (a < crit - 1e-3) {
            assert_true(optics_refract(arriving(a), n, N_GLASS, &t));
            double s2 = sin(a) * 1.5;
            assert_vec_near(t, v3((real)s2, (real)-sqrt(1 - s2 * s2), 0), 16 * TOL);
        } else if (a > crit + 1e-3) { /* total internal reflection */
            assert_false(optics_refract(arriving(a), n, N_GLASS, &t));
        }
    }
}

/* Fresnel's equations written with the angles: rs = -sin(i - t) / sin(i + t),
 * rp = tan(i - t) / tan(i + t); an independent form of what optics.h computes. */
static double fresnel_by_angles(double i, double n1, double n2)
{
    double st = n1 / n2 * sin(i);
    if (st >= 1)
        return 1;
    double t = asin(st);
    if (i == 0)
        return pow((n1 - n2) / (n1 + n2), 2);
    double rs = sin(i - t) / sin(i + t), rp = tan(i - t) / tan(i + t);
    return 0.5 * (rs * rs + rp * rp);
}

static void fresnel_at_normal_grazing_and_critical_angles(void **state)
{
    (void)state;
    const real eta_in = R(1) / N_GLASS, eta_out = N_GLASS;
    /* normal incidence: ((n1 - n2) / (n1 + n2))^2 = 0.04, both ways, both models */
    for (int m = 0; m < 2; m++) {
        assert_float_equal(optics_fresnel((FresnelModel)m, 1, eta_in), 0.04, 1e-6);
        assert_float_equal(optics_fresnel((FresnelModel)m, 1, eta_out), 0.04, 1e-6);
        /* grazing: everything reflected */
        assert_float_equal(optics_fresnel((FresnelModel)m, 0, eta_in), 1, 1e-6);
    }
    /* the exact form against the angle form, entering and leaving glass */
    for (double a = 0; a < 1.57; a += 0.01) {
        assert_float_equal(optics_fresnel_exact((real)cos(a), eta_in), fresnel_by_angles(a, 1, 1.5), 2e-5);
        assert_float_equal(optics_fresnel_exact((real)cos(a), eta_out), fresnel_by_angles(a, 1.5, 1), 2e-5);
    }
    /* Brewster's angle, tan i = n2 / n1: the p wave is not reflected at all */
    double b = atan(1.5), tb = asin(sin(b) / 1.5);
    assert_float_equal(optics_fresnel_exact((real)cos(b), eta_in), 0.5 * pow(sin(b - tb) / sin(b + tb), 2), 1e-6);
    /* the critical angle leaving glass: rising to 1 just below it, 1 at and past it */
    double crit = asin(1 / 1.5);
    for (int m = 0; m < 2; m++) {
        real below = optics_fresnel((FresnelModel)m, (real)cos(crit - 1e-4), eta_out);
        assert_true(below > R(0.8) && below < R(1));
        assert_float_equal(optics_fresnel((FresnelModel)m, (real)cos(crit + 1e-4), eta_out), 1, 0);
        assert_float_equal(optics_fresnel((FresnelModel)m, (real)cos(1.2), eta_out), 1, 0);
    }
    /* Schlick is an approximation: within a few hundredths of the exact form */
    double worst = 0;
    for (double a = 0; a < 1.57; a += 0.01)
        worst = fmax(worst, fabs((double)optics_fresnel_schlick((real)cos(a), eta_in) -
                                 (double)optics_fresnel_exact((real)cos(a), eta_in)));
    assert_true(worst > 1e-3 && worst < 0.05);
}

static Scene *glass_scene(real radius, real ior)
{
    Scene *s = scene_create();
    assert_non_null(s);
    s->ambient = s->background = v3_splat(0);
    Material glass = {.kd = v3_splat(0), .ks = v3_splat(0), .shininess = 1, .texture = -1, .ior = ior, .kt = v3_splat(1)};
    uint32_t id;
    assert_int_equal(scene_add_material(s, glass, &id, NULL), 0);
    Sphere sp = {v3(0, 0, 0), radius, id};
    assert_int_equal(scene_add_sphere(s, sp, NULL), 0);
    Err err;
    if (scene_check(s, &err))
        fail_msg("%s", err.msg);
    return s;
}

/* A ray parallel to the axis of a ball lens, traced the way the shader
 * refracts (trace_surface's normal and side, the offset origin), crosses
 * the axis where geometry puts it: incidence i = asin(h / R), refraction
 * r = asin(sin i / n), exit point at polar angle i + pi - 2r, deviation
 * D = 2 (i - r). */
static void a_ray_through_a_glass_sphere_meets_the_axis_where_geometry_says(void **state)
{
    (void)state;
    const double R_ = 1, n = 1.5;
    Scene *s = glass_scene((real)R_, (real)n);
    for (double h = 0.1; h < 0.95; h += 0.1) {
        Ray r = ray_make(v3((real)h, 0, 10), v3(0, 0, -1), 0, REAL_INF);
        for (int crossing = 0; crossing < 2; crossing++) {
            Hit hit;
            assert_true(trace_closest(world_now(s), &r, &hit));
            Surface sf;
            trace_surface(world_now(s), &r, &hit, &sf);
            assert_int_equal(sf.inside, crossing); /* in, then out */
            vec3 t = v3_splat(0);
            real eta = sf.inside ? sf.mat->ior : R(1) / sf.mat->ior;
            assert_true(optics_refract(r.dir, sf.ns, eta, &t));
            r = ray_make(trace_offset_origin(sf.p, v3_neg(sf.ng), sf.err), v3_norm(t), 0, REAL_INF);
        }
        double i = asin(h / R_), rr = asin(sin(i) / n), D = 2 * (i - rr);
        double x2 = R_ * sin(2 * rr - i), z2 = -R_ * cos(i - 2 * rr);
        double z_axis = z2 - x2 / sin(D) * cos(D);
        /* the traced exit ray, followed to x = 0 */
        assert_float_equal(r.org.x, x2, 1e-5);
        assert_float_equal(r.org.z, z2, 1e-5);
        assert_float_equal(r.dir.x, -sin(D), 1e-5);
        double sx = -(double)r.org.x / (double)r.dir.x;
        assert_float_equal((double)r.org.z + sx * (double)r.dir.z, z_axis, 1e-4 * fabs(z_axis) + 1e-5);
    }
    scene_destroy(s);
}

static vec3 look(Scene *s, vec3 eye, vec3 dir, RayStats *st)
{
    Ray r = ray_make(eye, v3_norm(dir), 0, REAL_INF);
    return shade_ray(world_now(s), &r, st, NULL);
}

/* A mirror sphere in front of an emissive wall: the centre pixel is kr
 * times the wall's emission; depth 0 shows only the mirror's own (black)
 * surface, and a cutoff above kr traces nothing. */
static void a_mirror_shows_kr_times_what_it_reflects(void **state)
{
    (void)state;
    Scene *s = scene_create();
    s->ambient = s->background = v3_splat(0);
    Material mirror = {.kd = v3_splat(0), .ks = v3_splat(0), .shininess = 1, .texture = -1, .kr = v3(R(0.9), R(0.5), R(0.25))};
    Material lamp = {.kd = v3_splat(0), .ks = v3_splat(0), .shininess = 1, .texture = -1, .ke = v3(1, 2, 4)};
    uint32_t m, l;
    assert_int_equal(scene_add_material(s, mirror, &m, NULL), 0);
    assert_int_equal(scene_add_material(s, lamp, &l, NULL), 0);
    assert_int_equal(scene_add_sphere(s, (Sphere){v3(0, 0, 0), 1, m}, NULL), 0);
    assert_int_equal(scene_add_plane(s, plane_make(v3(0, 0, 5), v3(0, 0, -1), l), NULL), 0);
    Err err;
    assert_int_equal(scene_check(s, &err), 0);
    const World *w = world_now(s);
    assert_true(world_has(w, FEAT_REFLECT) && world_has(w, FEAT_EMIT) && !world_has(w, FEAT_REFRACT));
    RayStats st = {0, 0, 0};
    /* straight at the sphere from behind the wall's side: reflected back onto the wall */
    vec3 c = look(s, v3(0, 0, 3), v3(0, 0, -1), &st);
    assert_vec_near(c, v3(R(0.9), 1, 1), 1e-5);
    assert_int_equal(st.secondary, 1);
    s->settings.depth = 0;
    assert_vec_near(look(s, v3(0, 0, 3), v3(0, 0, -1), &st), v3(0, 0, 0), 0);
    s->settings.depth = 5;
    s->settings.cutoff = R(0.95);
    st.secondary = 0;
    assert_vec_near(look(s, v3(0, 0, 3), v3(0, 0, -1), &st), v3(0, 0, 0), 0);
    assert_int_equal(st.secondary, 0);
    scene_destroy(s);
}

/* Through a clear glass sphere along its axis to an emissive wall: what
 * arrives is (1 - F)^2 of it (F = 0.04 at each face), plus nothing
 * reflected (a black background behind the camera).  Absorbing glass takes
 * exp(-absorb * 2R) of that again. */
static void glass_transmits_one_minus_fresnel_and_absorbs_by_beer_lambert(void **state)
{
    (void)state;
    for (int absorbing = 0; absorbing < 2; absorbing++) {
        Scene *s = scene_create();
        s->ambient = s->background = v3_splat(0);
        Material glass = {.kd = v3_splat(0), .ks = v3_splat(0), .shininess = 1, .texture = -1, .ior = N_GLASS,
                          .kt = v3_splat(1), .absorb = absorbing ? v3(R(0.1), R(0.5), 1) : v3_splat(0)};
        Material lamp = {.kd = v3_splat(0), .ks = v3_splat(0), .shininess = 1, .texture = -1, .ke = v3(1, 1, 1)};
        uint32_t g, l;
        assert_int_equal(scene_add_material(s, glass, &g, NULL), 0);
        assert_int_equal(scene_add_material(s, lamp, &l, NULL), 0);
        assert_int_equal(scene_add_sphere(s, (Sphere){v3(0, 0, 0), 1, g}, NULL), 0);
        assert_int_equal(scene_add_plane(s, plane_make(v3(0, 0, -5), v3(0, 0, 1), l), NULL), 0);
        Err err;
        assert_int_equal(scene_check(s, &err), 0);
        RayStats st = {0, 0, 0};
        vec3 c = look(s, v3(0, 0, 3), v3(0, 0, -1), &st);
        double through = 0.96 * 0.96;
        vec3 want = absorbing ? v3((real)(through * exp(-0.2)), (real)(through * exp(-1.0)), (real)(through * exp(-2.0)))
                              : v3_splat((real)through);
        assert_vec_near(c, want, 1e-5);
        scene_destroy(s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reflection_mirrors_about_the_normal),
        cmocka_unit_test(refraction_follows_snell),
        cmocka_unit_test(fresnel_at_normal_grazing_and_critical_angles),
        cmocka_unit_test(a_ray_through_a_glass_sphere_meets_the_axis_where_geometry_says),
        cmocka_unit_test(a_mirror_shows_kr_times_what_it_reflects),
        cmocka_unit_test(glass_transmits_one_minus_fresnel_and_absorbs_by_beer_lambert),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    world_now_free();
    return rc;
}

/* scene_default.c - the built-in scene: small, but it shows every feature a
 * newcomer should see working (shadows, the spot cone, texture filtering,
 * smooth normals, Phong highlights, a mirror, glass, a lamp and its soft
 * shadows) without any file on disk. */
#include "scene/scene_default.h"

#include "base/dmath.h"

#include <stdlib.h>

int mesh_torus_knot(Mesh *m, int segments, int sides, Err *err)
{
    if (mesh_init(m, MESH_NORMALS, err))
        return -1;
    const int P = 2, Q = 3;
    const real tube = R(0.35);
    vec3 *ring = malloc((size_t)segments * (size_t)sides * 2 * sizeof *ring);
    if (!ring) {
        mesh_free(m);
        return err_set(err, "out of memory");
    }
    for (int i = 0; i < segments; i++) {
        real phi = R(2) * REAL_PI * (real)i / (real)segments, h = R(1e-3);
        vec3 c[3];
        for (int k = 0; k < 3; k++) {
            const real a = phi + (real)(k - 1) * h;
            real sq, cq, sp, cp;
            dmath_sincosr(Q * a, &sq, &cq);
            dmath_sincosr(P * a, &sp, &cp);
            const real r = cq + R(2);
            c[k] = v3(r * cp, r * sp, -sq);
        }
        vec3 t = v3_norm(v3_sub(c[2], c[0]));
        vec3 acc = v3_sub(v3_add(c[2], c[0]), v3_scale(c[1], R(2)));
        vec3 b = v3_norm(v3_cross(t, acc)); /* Frenet frame: the knot's curvature never vanishes */
        vec3 n = v3_cross(b, t);
        for (int j = 0; j < sides; j++) {
            real th = R(2) * REAL_PI * (real)j / (real)sides;
            real st, ct;
            dmath_sincosr(th, &st, &ct);
            vec3 dir = v3_add(v3_scale(n, ct), v3_scale(b, st));
            ring[2 * (i * sides + j)] = v3_madd(c[1], dir, tube);
            ring[2 * (i * sides + j) + 1] = dir;
        }
    }
    int rc = 0;
    for (int i = 0; i < segments && rc == 0; i++)
        for (int j = 0; j < sides && rc == 0; j++) {
            int i1 = (i + 1) % segments, j1 = (j + 1) % sides;
            int q[4] = {i * sides + j, i1 * sides + j, i1 * sides + j1, i * sides + j1};
            vec3 p[3], nn[3];
            const int tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
            for (int t = 0; t < 2 && rc == 0; t++) {
                for (int k = 0; k < 3; k++) {
                    p[k] = ring[2 * q[tris[t][k]]];
                    nn[k] = ring[2 * q[tris[t][k]] + 1];
                }
                if (!mesh_tri_is_degenerate(p))
                    rc = mesh_add(m, p, nn, NULL, NULL, 0, err);
            }
        }
    free(ring);
    if (rc)
        mesh_free(m);
    return rc;
}

/* 64x64 texels: a checkerboard of hues with a ring, coarse enough that
 * nearest and bilinear filtering look clearly different up close. */
static Texture *default_texture(void)
{
    enum { N = 64 };
    static uint8_t px[N * N * 3];
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            int check = ((x / 8) + (y / 8)) & 1;
            real dx = (real)x - R(31.5), dy = (real)y - R(31.5), d = sqrt(dx * dx + dy * dy);
            int ring = d > R(20) && d < R(25);
            uint8_t *p = &px[3 * (y * N + x)];
            p[0] = ring ? 250 : (uint8_t)(check ? 40 + 3 * x : 230);
            p[1] = ring ? 220 : (uint8_t)(check ? 60 + 2 * y : 230);
            p[2] = ring ? 40 : (uint8_t)(check ? 200 : 220);
        }
    return texture_from_rgb8(N, N, px);
}

static Material mat(real r, real g, real b, real spec, real shininess)
{
    Material m = {.kd = v3(r, g, b), .ks = v3_splat(spec), .shininess = shininess, .texture = -1};
    return m;
}

/* Colours are linear light (the values of sRGB colours decoded: the red
 * sphere's 0.69 0.019 0.01 is sRGB 0.85 0.15 0.1). */
int scene_default(Scene **out, const BvhOptions *opt, Err *err)
{
    *out = NULL;
    Scene *s = scene_create();
    if (!s)
        return err_set(err, "out of memory");
    camera_look_at(&s->camera, v3(0, R(2.4), R(7)), v3(0, R(0.8), 0), 0, camera_zoom_for_fov(55));
    s->ambient = v3_splat(R(0.015));
    s->background = v3(R(0.007), R(0.01), R(0.022));
    uint32_t floor, red, blue, green, gold, pic, tex, mirror, glass;
    Texture *t = default_texture();
    if (!t) {
        scene_destroy(s);
        return err_set(err, "out of memory");
    }
    Mesh knot;
    Model *model = NULL;
    int rc = scene_add_texture(s, t, &tex, err);
    Material picture = mat(1, 1, 1, R(0.1), 8);
    picture.texture = (int32_t)tex;
    rc = rc ? rc : scene_add_material(s, mat(R(0.52), R(0.52), R(0.48), 0, 1), &floor, err);
    rc = rc ? rc : scene_add_material(s, mat(R(0.69), R(0.019), R(0.01), R(0.6), 40), &red, err);
    rc = rc ? rc : scene_add_material(s, mat(R(0.019), R(0.073), R(0.79), R(0.4), 20), &blue, err);
    rc = rc ? rc : scene_add_material(s, mat(R(0.033), R(0.52), R(0.051), R(0.3), 10), &green, err);
    rc = rc ? rc : scene_add_material(s, mat(R(0.79), R(0.38), R(0.033), R(0.8), 60), &gold, err);
    rc = rc ? rc : scene_add_material(s, picture, &pic, err);
    /* a mirror, and glass with a faint blue-green tint deepening with thickness */
    Material chrome = mat(0, 0, 0, R(0.6), 200), crystal = mat(0, 0, 0, R(0.9), 300);
    chrome.kr = v3(R(0.85), R(0.85), R(0.88));
    crystal.ior = R(1.5);
    crystal.kt = v3_splat(1);
    crystal.absorb = v3(R(0.25), R(0.08), R(0.12));
    rc = rc ? rc : scene_add_material(s, chrome, &mirror, err);
    rc = rc ? rc : scene_add_material(s, crystal, &glass, err);
    rc = rc ? rc : scene_add_plane(s, plane_make(v3(0, 0, 0), v3(0, 1, 0), floor), err);
    rc = rc ? rc : scene_add_sphere(s, (Sphere){v3(R(-1.9), R(0.75), R(0.4)), R(0.75), red}, err);
    rc = rc ? rc : scene_add_sphere(s, (Sphere){v3(R(1.9), R(0.55), R(0.9)), R(0.55), blue}, err);
    rc = rc ? rc : scene_add_sphere(s, (Sphere){v3(R(-0.3), R(0.3), R(2.0)), R(0.3), green}, err);
    rc = rc ? rc : scene_add_sphere(s, (Sphere){v3(R(-1.05), R(0.45), R(1.75)), R(0.45), mirror}, err);
    rc = rc ? rc : scene_add_sphere(s, (Sphere){v3(R(0.85), R(0.5), R(1.9)), R(0.5), glass}, err);
    /* the picture: a quad standing behind the objects, texture coordinates over [0,1]^2 */
    vec3 a = v3(R(-1.6), R(0.2), R(-2.2)), b = v3(R(1.6), R(0.2), R(-2.2));
    vec3 c = v3(R(1.6), R(2.6), R(-2.2)), d = v3(R(-1.6), R(2.6), R(-2.2));
    const vec3 t1[3] = {a, b, c}, t2[3] = {a, c, d};
    const real uv1[6] = {0, 0, 1, 0, 1, 1}, uv2[6] = {0, 0, 1, 1, 0, 1};
    rc = rc ? rc : scene_add_triangle(s, t1, NULL, uv1, pic, err);
    rc = rc ? rc : scene_add_triangle(s, t2, NULL, uv2, pic, err);
    rc = rc ? rc : mesh_torus_knot(&knot, 192, 16, err);
    if (rc == 0) {
        rc = model_from_mesh(&model, &knot, opt, err);
        mesh_free(&knot);
    }
    uint32_t mid = 0;
    rc = rc ? rc : scene_add_model(s, model, &mid, err);
    if (rc == 0) {
        Instance in = instance_make(mid, v3(R(0.2), R(1.05), R(-0.2)), v3(R(70), R(10), 0), R(0.32));
        in.material = (int32_t)gold;
        rc = scene_add_instance(s, in, err);
    }
    /* a round lamp in view, top right: an emissive sphere around a sphere
     * light (its lamp, scene.h), with its soft shadows (3 x 3 shadow rays) */
    Material bulb = mat(0, 0, 0, 0, 1);
    bulb.ke = v3_splat(4);
    uint32_t lamp;
    const vec3 at = v3(R(1.8), R(3.1), R(1.8));
    rc = rc ? rc : scene_add_material(s, bulb, &lamp, err);
    rc = rc ? rc : scene_add_sphere(s, (Sphere){at, R(0.3), lamp}, err);
    rc = rc ? rc : scene_add_light(s, light_sphere(at, R(0.3), 3, v3(1, 1, 1), R(0.75), 0), err);
    rc = rc ? rc : scene_add_light(s, light_spot(v3(R(-2.5), R(5), R(2.5)), v3(R(0.35), -1, R(-0.45)), 36, 8,
                                                 v3(1, R(0.85), R(0.6)), R(0.7), 0), err);
    rc = rc ? rc : scene_check(s, err);
    if (rc) {
        scene_destroy(s);
        return -1;
    }
    *out = s;
    return 0;
}

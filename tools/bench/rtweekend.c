/* rtweekend.c - the reference path tracer of issue 31: a plain CPU renderer
 * written as "Ray Tracing in One Weekend" describes it (spheres; Lambertian,
 * metal with fuzz and dielectric materials; recursive scattering; samples in
 * a loop), with the sphere BVH of "The Next Week", so that lanray's path
 * integrator is timed against the seed's own baseline on the same scene.
 *
 *   rtweekend [--width W] [--height H] [--spp N] [--depth D] [--threads T]
 *             [--seed S] [--sky R,G,B] [--furnace] [-o OUT.ppm]
 *             [--write-scene FILE.scene]
 *
 * The scene is the seed's benchmark: 100 spheres of radius 0.2 on a 10 x 10
 * grid, positions jittered, materials drawn from seed S (Lambertian with
 * probability 0.8, albedo = random RGB squared; metal 0.15, albedo (random
 * + 0.5) / 2 per channel, fuzz up to 0.5; glass 0.05, index 1.5), on the
 * book's ground sphere (radius 1000, albedo 0.5) beside its three large
 * spheres (glass; Lambertian 0.4 0.2 0.1; metal 0.7 0.6 0.5), seen from
 * (13, 2, 3) towards the origin with a vertical field of view of 20
 * degrees.  Rays that leave the scene see the book's sky (white to blue by
 * the ray's height), or a constant --sky.  --furnace: one Lambertian sphere
 * of albedo 1 under a constant sky of 1 (a white furnace: every pixel must
 * come out 1).  Pixels are written as sRGB codes (PPM, P6), each channel
 * the mean of N samples; every random number comes from the pixel and the
 * sample (a hash), so that the picture does not depend on the threads.
 * --write-scene writes the same scene as a lanray scene file for its path
 * integrator (the book's depth and Schlick's reflectance; a constant --sky
 * as the background, else the book's sky's mean, and as the ambient light
 * where lanray's Whitted integrator is asked for instead). */
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/timer.h"

#define PI 3.14159265358979323846

typedef struct {
    double x, y, z;
} V3;

static V3 v3(double x, double y, double z) { return (V3){x, y, z}; }
static V3 add(V3 a, V3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static V3 sub(V3 a, V3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static V3 mul(V3 a, V3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static V3 scale(V3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static V3 cross(V3 a, V3 b) { return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
static V3 unit(V3 a) { return scale(a, 1.0 / sqrt(dot(a, a))); }
static double axis(V3 a, int k) { return k == 0 ? a.x : k == 1 ? a.y : a.z; }

/* The book's random numbers, drawn from a per-sample generator (xorshift64*
 * seeded by a hash of the pixel and the sample). */
typedef struct {
    uint64_t s;
} Rng;

static uint64_t mix64(uint64_t x)
{
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

static double rnd(Rng *r)
{
    r->s ^= r->s >> 12;
    r->s ^= r->s << 25;
    r->s ^= r->s >> 27;
    return (double)((r->s * 0x2545f4914f6cdd1dULL) >> 11) * 0x1.0p-53;
}

static double rnd_in(Rng *r, double lo, double hi) { return lo + (hi - lo) * rnd(r); }

static V3 random_unit_vector(Rng *r)
{
    for (;;) {
        V3 p = v3(rnd_in(r, -1, 1), rnd_in(r, -1, 1), rnd_in(r, -1, 1));
        double l2 = dot(p, p);
        if (l2 > 1e-160 && l2 <= 1)
            return scale(p, 1.0 / sqrt(l2));
    }
}

typedef enum { LAMBERTIAN, METAL, DIELECTRIC } MatKind;

typedef struct {
    MatKind kind;
    V3 albedo;
    double fuzz, ir;
} Mat;

typedef struct {
    V3 centre;
    double radius;
    Mat mat;
} Sphere;

typedef struct {
    V3 lo, hi;
    int left, right; /* children, or -1 and the sphere in `left` for a leaf (right = -1 - sphere) */
} Node;

typedef struct {
    Sphere *s;
    int n;
    Node *nodes;
    int nnodes;
    V3 sky;        /* a constant sky, where sky_const */
    int sky_const;
    int width, height, spp, depth;
    V3 origin, corner, horiz, vert; /* the book's camera */
    uint8_t *out;
    int next_row;
    pthread_mutex_t mu;
} Scene;

/* The book's BVH: spheres sorted along a random axis, split in halves. */
static int cmp_axis;
static int by_axis(const void *a, const void *b)
{
    const Sphere *p = a, *q = b;
    double u = axis(p->centre, cmp_axis) - p->radius, v = axis(q->centre, cmp_axis) - q->radius;
    return (u > v) - (u < v);
}

static int bvh_build(Scene *sc, Sphere *s, int n, Rng *r)
{
    int me = sc->nnodes++;
    Node nd = {v3(1e300, 1e300, 1e300), v3(-1e300, -1e300, -1e300), -1, -1};
    for (int i = 0; i < n; i++) {
        V3 e = v3(s[i].radius, s[i].radius, s[i].radius), a = sub(s[i].centre, e), b = add(s[i].centre, e);
        nd.lo = v3(fmin(nd.lo.x, a.x), fmin(nd.lo.y, a.y), fmin(nd.lo.z, a.z));
        nd.hi = v3(fmax(nd.hi.x, b.x), fmax(nd.hi.y, b.y), fmax(nd.hi.z, b.z));
    }
    if (n == 1) {
        nd.right = -1 - (int)(s - sc->s);
    } else {
        cmp_axis = (int)(rnd(r) * 3) % 3;
        qsort(s, (size_t)n, sizeof *s, by_axis);
        nd.left = bvh_build(sc, s, n / 2, r);
        nd.right = bvh_build(sc, s + n / 2, n - n / 2, r);
    }
    sc->nodes[me] = nd;
    return me;
}

static int box_hit(const Node *b, V3 o, V3 inv, double tmin, double tmax)
{
    for (int k = 0; k < 3; k++) {
        double t0 = (axis(b->lo, k) - axis(o, k)) * axis(inv, k), t1 = (axis(b->hi, k) - axis(o, k)) * axis(inv, k);
        if (t0 > t1) {
            double t = t0;
            t0 = t1, t1 = t;
        }
        tmin = t0 > tmin ? t0 : tmin;
        tmax = t1 < tmax ? t1 : tmax;
        if (tmax <= tmin)
            return 0;
    }
    return 1;
}

typedef struct {
    double t;
    V3 p, n;
    int front;
    const Mat *mat;
} HitRec;

static int sphere_hit(const Sphere *s, V3 o, V3 d, double tmin, double tmax, HitRec *h)
{
    V3 oc = sub(o, s->centre);
    double a = dot(d, d), hb = dot(oc, d), c = dot(oc, oc) - s->radius * s->radius, disc = hb * hb - a * c;
    if (disc < 0)
        return 0;
    double sq = sqrt(disc), t = (-hb - sq) / a;
    if (t < tmin || t > tmax) {
        t = (-hb + sq) / a;
        if (t < tmin || t > tmax)
            return 0;
    }
    h->t = t;
    h->p = add(o, scale(d, t));
    V3 outward = scale(sub(h->p, s->centre), 1.0 / s->radius);
    h->front = dot(d, outward) < 0;
    h->n = h->front ? outward : scale(outward, -1);
    h->mat = &s->mat;
    return 1;
}

static int world_hit(const Scene *sc, V3 o, V3 d, double tmin, double tmax, HitRec *h)
{
    V3 inv = v3(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
    int stack[64], sp = 0, any = 0;
    stack[sp++] = 0;
    while (sp) {
        const Node *nd = &sc->nodes[stack[--sp]];
        if (!box_hit(nd, o, inv, tmin, tmax))
            continue;
        if (nd->left < 0) {
            if (sphere_hit(&sc->s[-1 - nd->right], o, d, tmin, tmax, h))
                any = 1, tmax = h->t;
        } else if (sp + 2 <= 64) {
            stack[sp++] = nd->left;
            stack[sp++] = nd->right;
        }
    }
    return any;
}

static double reflectance(double cosine, double ratio)
{
    double r0 = (1 - ratio) / (1 + ratio);
    r0 = r0 * r0;
    return r0 + (1 - r0) * pow(1 - cosine, 5);
}

/* The book's material scattering: 0 where the ray is absorbed. */
static int scatter(const HitRec *h, V3 d, Rng *r, V3 *att, V3 *out)
{
    const Mat *m = h->mat;
    if (m->kind == LAMBERTIAN) {
        V3 dir = add(h->n, random_unit_vector(r));
        if (fabs(dir.x) < 1e-8 && fabs(dir.y) < 1e-8 && fabs(dir.z) < 1e-8)
            dir = h->n;
        *att = m->albedo, *out = dir;
        return 1;
    }
    V3 u = unit(d);
    if (m->kind == METAL) {
        V3 refl = sub(u, scale(h->n, 2 * dot(u, h->n)));
        *out = add(unit(refl), scale(random_unit_vector(r), m->fuzz));
        *att = m->albedo;
        return dot(*out, h->n) > 0;
    }
    double ratio = h->front ? 1.0 / m->ir : m->ir, cos_t = fmin(dot(scale(u, -1), h->n), 1.0),
           sin_t = sqrt(1 - cos_t * cos_t);
    if (ratio * sin_t > 1 || reflectance(cos_t, ratio) > rnd(r)) {
        *out = sub(u, scale(h->n, 2 * dot(u, h->n)));
    } else {
        V3 perp = scale(add(u, scale(h->n, cos_t)), ratio);
        *out = add(perp, scale(h->n, -sqrt(fabs(1 - dot(perp, perp)))));
    }
    *att = v3(1, 1, 1);
    return 1;
}

/* The book's ray_color, recursive. */
static V3 ray_color(const Scene *sc, V3 o, V3 d, int depth, Rng *r)
{
    if (depth <= 0)
        return v3(0, 0, 0);
    HitRec h = {0};
    if (world_hit(sc, o, d, 0.001, INFINITY, &h)) {
        V3 att, out;
        if (!scatter(&h, d, r, &att, &out))
            return v3(0, 0, 0);
        return mul(att, ray_color(sc, h.p, out, depth - 1, r));
    }
    if (sc->sky_const)
        return sc->sky;
    double a = 0.5 * (unit(d).y + 1.0);
    return add(scale(v3(1, 1, 1), 1 - a), scale(v3(0.5, 0.7, 1.0), a));
}

static uint8_t srgb_code(double v)
{
    v = v <= 0 ? 0 : v >= 1 ? 1 : v;
    double s = v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055;
    return (uint8_t)(s * 255 + 0.5);
}

static void *render_rows(void *arg)
{
    Scene *sc = arg;
    for (;;) {
        pthread_mutex_lock(&sc->mu);
        int y = sc->next_row++;
        pthread_mutex_unlock(&sc->mu);
        if (y >= sc->height)
            return NULL;
        for (int x = 0; x < sc->width; x++) {
            V3 c = v3(0, 0, 0);
            for (int s = 0; s < sc->spp; s++) {
                Rng r = {mix64(((uint64_t)y << 40) ^ ((uint64_t)x << 20) ^ (uint64_t)s) | 1};
                double u = (x + rnd(&r)) / sc->width, v = 1 - (y + rnd(&r)) / sc->height;
                V3 d = sub(add(sc->corner, add(scale(sc->horiz, u), scale(sc->vert, v))), sc->origin);
                c = add(c, ray_color(sc, sc->origin, d, sc->depth, &r));
            }
            uint8_t *px = sc->out + 3 * ((size_t)y * sc->width + x);
            px[0] = srgb_code(c.x / sc->spp), px[1] = srgb_code(c.y / sc->spp), px[2] = srgb_code(c.z / sc->spp);
        }
    }
}

static Mat mat(MatKind k, V3 albedo, double fuzz, double ir) { return (Mat){k, albedo, fuzz, ir}; }

/* The seed's 100 spheres, the ground and the book's three large spheres. */
static int scene_make(Scene *sc, uint64_t seed, int furnace)
{
    sc->s = calloc(128, sizeof *sc->s);
    if (!sc->s)
        return -1;
    if (furnace) {
        sc->s[sc->n++] = (Sphere){v3(0, 0, 0), 1, mat(LAMBERTIAN, v3(1, 1, 1), 0, 0)};
        return 0;
    }
    Rng r = {mix64(seed) | 1};
    sc->s[sc->n++] = (Sphere){v3(0, -1000, 0), 1000, mat(LAMBERTIAN, v3(0.5, 0.5, 0.5), 0, 0)};
    for (int a = -5; a < 5; a++)
        for (int b = -5; b < 5; b++) {
            double choose = rnd(&r);
            V3 c = v3(a + 0.9 * rnd(&r), 0.2, b + 0.9 * rnd(&r));
            Mat m;
            if (choose < 0.8) {
                V3 p = v3(rnd(&r), rnd(&r), rnd(&r)), q = v3(rnd(&r), rnd(&r), rnd(&r));
                m = mat(LAMBERTIAN, mul(p, q), 0, 0);
            } else if (choose < 0.95) {
                V3 al = v3((rnd(&r) + 0.5) / 2, (rnd(&r) + 0.5) / 2, (rnd(&r) + 0.5) / 2);
                m = mat(METAL, al, rnd_in(&r, 0, 0.5), 0);
            } else {
                m = mat(DIELECTRIC, v3(1, 1, 1), 0, 1.5);
            }
            sc->s[sc->n++] = (Sphere){c, 0.2, m};
        }
    sc->s[sc->n++] = (Sphere){v3(0, 1, 0), 1, mat(DIELECTRIC, v3(1, 1, 1), 0, 1.5)};
    sc->s[sc->n++] = (Sphere){v3(-4, 1, 0), 1, mat(LAMBERTIAN, v3(0.4, 0.2, 0.1), 0, 0)};
    sc->s[sc->n++] = (Sphere){v3(4, 1, 0), 1, mat(METAL, v3(0.7, 0.6, 0.5), 0, 0)};
    return 0;
}

/* The book's camera: from, towards, vertical field of view. */
static void camera_set(Scene *sc, V3 from, V3 at, double vfov)
{
    double h = tan(vfov * PI / 360), vh = 2 * h, vw = vh * sc->width / sc->height;
    V3 w = unit(sub(from, at)), u = unit(cross(v3(0, 1, 0), w)), v = cross(w, u);
    sc->origin = from;
    sc->horiz = scale(u, vw);
    sc->vert = scale(v, vh);
    sc->corner = sub(sub(sub(from, scale(sc->horiz, 0.5)), scale(sc->vert, 0.5)), w);
}

/* A file written under path.tmp, closed and renamed to path: no partial
 * file left behind where writing fails. */
static int file_finish(FILE *f, const char *tmp, const char *path)
{
    int bad = ferror(f);
    bad |= fclose(f);
    if (bad || rename(tmp, path)) {
        remove(tmp);
        return -1;
    }
    return 0;
}

/* The same scene for lanray: spheres and materials by the book's meaning
 * (metal: a mirror of that colour, its fuzz as roughness; glass: ior 1.5),
 * the camera's horizontal field of view from the book's vertical one. */
static int scene_write(const Scene *sc, const char *path, V3 from, V3 at, double vfov)
{
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f)
        return -1;
    double hfov = 2 * atan(tan(vfov * PI / 360) * sc->width / sc->height) * 180 / PI;
    fprintf(f, "# the seed's benchmark scene, written by tools/bench/rtweekend --write-scene\n");
    fprintf(f, "camera position %.17g %.17g %.17g lookat %.17g %.17g %.17g fov %.17g\n", from.x, from.y, from.z, at.x,
            at.y, at.z, hfov);
    V3 sky = sc->sky_const ? sc->sky : v3(0.75, 0.85, 1.0);
    fprintf(f, "background %.17g %.17g %.17g\nambient %.17g %.17g %.17g\n", sky.x, sky.y, sky.z, sky.x, sky.y, sky.z);
    /* the book's light transport for the path integrator: its depth (the
     * camera ray and 49 bounces), Schlick's reflectance */
    fprintf(f, "settings width %d height %d integrator path depth %d fresnel schlick\n", sc->width, sc->height,
            sc->depth - 1);
    for (int i = 0; i < sc->n; i++) {
        const Sphere *s = &sc->s[i];
        const Mat *m = &s->mat;
        if (m->kind == LAMBERTIAN)
            fprintf(f, "material m%d diffuse %.17g %.17g %.17g\n", i, m->albedo.x, m->albedo.y, m->albedo.z);
        else if (m->kind == METAL)
            fprintf(f, "material m%d reflect %.17g %.17g %.17g roughness %.17g\n", i, m->albedo.x, m->albedo.y,
                    m->albedo.z, m->fuzz);
        else
            fprintf(f, "material m%d ior %.17g\n", i, m->ir);
        fprintf(f, "sphere centre %.17g %.17g %.17g radius %.17g material m%d\n", s->centre.x, s->centre.y,
                s->centre.z, s->radius, i);
    }
    return file_finish(f, tmp, path);
}

static int write_ppm(const Scene *sc, const char *path)
{
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "wb");
    if (!f)
        return -1;
    fprintf(f, "P6\n%d %d\n255\n", sc->width, sc->height);
    fwrite(sc->out, 3, (size_t)sc->width * sc->height, f);
    return file_finish(f, tmp, path);
}

typedef struct {
    int width, height, spp, depth, threads, furnace;
    uint64_t seed;
    const char *out, *scene_out;
    int sky_const;
    V3 sky;
} Args;

static int parse_args(int argc, char **argv, Args *a)
{
    *a = (Args){.width = 400, .height = 225, .spp = 10, .depth = 50, .threads = 1, .seed = 1};
    for (int i = 1; i < argc; i++) {
        const char *k = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(k, "--furnace")) {
            a->furnace = 1;
            continue;
        }
        if (!v)
            return fprintf(stderr, "rtweekend: %s needs a value (see the header of tools/bench/rtweekend.c)\n", k), 2;
        i++;
        if (!strcmp(k, "--width"))
            a->width = atoi(v);
        else if (!strcmp(k, "--height"))
            a->height = atoi(v);
        else if (!strcmp(k, "--spp"))
            a->spp = atoi(v);
        else if (!strcmp(k, "--depth"))
            a->depth = atoi(v);
        else if (!strcmp(k, "--threads"))
            a->threads = atoi(v);
        else if (!strcmp(k, "--seed"))
            a->seed = strtoull(v, NULL, 10);
        else if (!strcmp(k, "-o"))
            a->out = v;
        else if (!strcmp(k, "--write-scene"))
            a->scene_out = v;
        else if (!strcmp(k, "--sky") && sscanf(v, "%lf,%lf,%lf", &a->sky.x, &a->sky.y, &a->sky.z) == 3)
            a->sky_const = 1;
        else
            return fprintf(stderr, "rtweekend: bad option %s %s\n", k, v), 2;
    }
    if (a->width < 1 || a->height < 1 || a->width > 16384 || a->height > 16384 || a->spp < 1 || a->depth < 1 ||
        a->threads < 1 || a->threads > 256)
        return fprintf(stderr, "rtweekend: sizes 1..16384, spp, depth and threads (1..256) at least 1\n"), 2;
    return 0;
}

int main(int argc, char **argv)
{
    Args a;
    int rc = parse_args(argc, argv, &a);
    if (rc)
        return rc;
    Scene sc = {.width = a.width, .height = a.height, .spp = a.spp, .depth = a.depth, .sky = a.sky,
                .sky_const = a.sky_const || a.furnace};
    if (a.furnace)
        sc.sky = v3(1, 1, 1);
    V3 from = a.furnace ? v3(0, 0, 4) : v3(13, 2, 3), at = v3(0, 0, 0);
    const double vfov = a.furnace ? 40 : 20;
    Rng r = {mix64(a.seed ^ 0x5eed) | 1};
    if (scene_make(&sc, a.seed, a.furnace) || !(sc.nodes = calloc(2 * (size_t)sc.n, sizeof *sc.nodes)) ||
        !(sc.out = malloc(3 * (size_t)sc.width * sc.height)))
        return fprintf(stderr, "rtweekend: out of memory\n"), 1;
    camera_set(&sc, from, at, vfov);
    if (a.scene_out && scene_write(&sc, a.scene_out, from, at, vfov))
        return fprintf(stderr, "rtweekend: cannot write %s\n", a.scene_out), 1;
    bvh_build(&sc, sc.s, sc.n, &r);
    pthread_mutex_init(&sc.mu, NULL);
    pthread_t th[256];
    double t0 = timer_now();
    for (int i = 0; i < a.threads; i++)
        pthread_create(&th[i], NULL, render_rows, &sc);
    for (int i = 0; i < a.threads; i++)
        pthread_join(th[i], NULL);
    double t = timer_now() - t0;
    printf("rtweekend: %dx%d, %d samples a pixel, %d spheres, %d threads: %.3f s\n", sc.width, sc.height, sc.spp, sc.n,
           a.threads, t);
    rc = a.out && write_ppm(&sc, a.out) ? (fprintf(stderr, "rtweekend: cannot write %s\n", a.out), 1) : 0;
    pthread_mutex_destroy(&sc.mu);
    free(sc.s);
    free(sc.nodes);
    free(sc.out);
    return rc;
}

/* embree_ref - reference renderer on Intel Embree (Debian's libembree3), for
 * the renderer benchmark (tools/bench/bench-render).
 *
 *   embree_ref SCENE [--width W] [--height H] [--threads T] [--repeat N] [-o out.png]
 *
 * It reads the same scene file with lanray's parser, flattens every model
 * instance into one world-space triangle mesh, and traces exactly lanray's
 * camera rays (camera_frame) and one shadow ray per light per hit, with
 * rtcIntersect1 and rtcOccluded1, on T threads of its own taking lines
 * through an atomic counter (Embree itself, building, is capped at T
 * threads too).  --robust sets RTC_SCENE_FLAG_ROBUST.  It reports the
 * build time (median of 3) and the bytes Embree holds per triangle (its
 * memory monitor: the tree and leaves, and the vertex and index buffers
 * the geometry shares with it).  Shading is the same Phong model, so both
 * programs do the same work per ray.  Prints rays per second like
 * lanray-render does.  Spheres and planes are not supported here: the
 * benchmark scenes are meshes only. */
#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <pthread.h>
#include <stdbool.h>
#include <sys/types.h>
#include <xmmintrin.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/camera.h"
#include "image/image.h"
#include "base/opt.h"
#include "base/srgb.h"
#include "scene/scene_parse.h"
#include "base/timer.h"
#include "scene/trace.h"

typedef struct {
    RTCScene scene;
    const Scene *s;
    CameraFrame cam;
    const float *vb; /* world-space vertices, three per triangle */
    uint8_t *pixels;
    vec3 kd, ks;
    real shininess;
    atomic_int next_line;
    atomic_ullong primary, shadow;
} Job;

static vec3 shade(Job *j, struct RTCIntersectContext *ctx, vec3 d, unsigned long long *nshadow)
{
    const Scene *s = j->s;
    struct RTCRayHit rh;
    rh.ray.org_x = j->cam.org.x, rh.ray.org_y = j->cam.org.y, rh.ray.org_z = j->cam.org.z;
    rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
    rh.ray.tnear = 0, rh.ray.tfar = INFINITY, rh.ray.time = 0, rh.ray.mask = 0xffffffffu, rh.ray.id = 0, rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(j->scene, ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return s->background;
    /* the hit point from its barycentrics on the triangle, as lanray has
     * it: o + t*d carries the error of t times the ray's length, which an
     * offset sized for the triangle's own error does not cover (isolated
     * shadow acne: 97 dark pixels in the bunny that lanray has lit) */
    const float *f = j->vb + 9 * (size_t)rh.hit.primID;
    real err;
    vec3 p = trace_triangle_point(v3(f[0], f[1], f[2]), v3(f[3], f[4], f[5]), v3(f[6], f[7], f[8]), rh.hit.u, rh.hit.v, &err);
    vec3 n = v3_norm(v3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
    if (v3_dot(n, d) > 0)
        n = v3_neg(n);
    vec3 col = v3_mul(s->ambient, j->kd), view = v3_neg(d);
    /* the same offset as lanray's: just beyond the hit point's error */
    vec3 origin = trace_offset_origin(p, n, err);
    for (uint32_t i = 0; i < s->light_count; i++) {
        const Light *l = &s->lights[i];
        vec3 L = v3_sub(l->pos, p);
        real dist = v3_len(L);
        L = v3_scale(L, R(1) / dist);
        real ndotl = v3_dot(n, L);
        if (ndotl <= 0)
            continue;
        struct RTCRay sr;
        sr.org_x = origin.x, sr.org_y = origin.y, sr.org_z = origin.z;
        sr.dir_x = L.x, sr.dir_y = L.y, sr.dir_z = L.z;
        sr.tnear = 0, sr.tfar = dist * (R(1) - R(64) * REAL_EPS), sr.time = 0, sr.mask = 0xffffffffu, sr.id = 0, sr.flags = 0;
        (*nshadow)++;
        rtcOccluded1(j->scene, ctx, &sr);
        if (sr.tfar < 0) /* Embree marks an occluded ray with tfar = -inf */
            continue;
        vec3 rad = v3_scale(l->color, l->intensity);
        col = v3_add(col, v3_scale(v3_mul(j->kd, rad), ndotl));
        real rv = v3_dot(v3_reflect(v3_neg(L), n), view);
        if (rv > 0)
            col = v3_add(col, v3_scale(v3_mul(j->ks, rad), pow(rv, j->shininess)));
    }
    return col;
}

/* Bytes Embree holds, from its memory monitor: buffers, tree and leaves. */
static atomic_long device_bytes;

static bool count_bytes(void *ptr, ssize_t bytes, bool post)
{
    (void)ptr, (void)post;
    atomic_fetch_add(&device_bytes, (long)bytes);
    return true;
}

#define BUILDS 3

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static void *worker(void *arg)
{
    Job *j = arg;
    /* flush denormals to zero, as Embree advises for its kernels */
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    unsigned long long np = 0, ns = 0;
    int y;
    while ((y = atomic_fetch_add(&j->next_line, 1)) < j->cam.height) {
        for (int x = 0; x < j->cam.width; x++) {
            vec3 d = v3_norm(camera_dir(&j->cam, (real)x + R(0.5), (real)y + R(0.5)));
            vec3 c = shade(j, &ctx, d, &ns);
            np++;
            uint8_t *px = &j->pixels[3 * ((size_t)y * j->cam.width + x)];
            for (int k = 0; k < 3; k++)
                px[k] = srgb_encode8(c.e[k]);
        }
    }
    atomic_fetch_add(&j->primary, np);
    atomic_fetch_add(&j->shadow, ns);
    return NULL;
}

/* What the command line says. */
typedef struct {
    const char *out, *scene_path;
    int width, height, threads, repeat, robust;
} Args;

/* Parses the command line into a: OPT_GO, or the exit status. */
static int parse_args(Args *a, int argc, char **argv)
{
    *a = (Args){.width = 1024, .height = 768, .threads = 2, .repeat = 1};
    const Opt opts[] = {
        {.name = "--output", .alias = "-o", .kind = OPT_STRING, .dst = &a->out, .arg = "FILE", .help = "write the image", .def = "none"},
        {.name = "--width", .kind = OPT_INT, .dst = &a->width, .arg = "W", .lo = 1, .hi = 16384, .help = "frame width"},
        {.name = "--height", .kind = OPT_INT, .dst = &a->height, .arg = "H", .lo = 1, .hi = 16384, .help = "frame height"},
        {.name = "--threads", .kind = OPT_INT, .dst = &a->threads, .arg = "T", .lo = 1, .hi = 256, .help = "render threads"},
        {.name = "--repeat", .kind = OPT_INT, .dst = &a->repeat, .arg = "N", .lo = 1, .hi = 100000,
         .help = "render N times, report the best time"},
        {.name = "--robust", .kind = OPT_FLAG, .dst = &a->robust,
         .help = "RTC_SCENE_FLAG_ROBUST: Embree's watertight traversal (slower)"},
        {0},
    };
    const char *args[1];
    OptSpec spec = {.prog = "embree_ref", .synopsis = "SCENE [options]",
                    .about = "Renders a mesh-only scene (model instances, point lights) on Intel Embree with lanray's camera\n"
                    "rays and shading, for make bench and tests/cli/embree.sh.",
                    .opts = opts, .args = args, .min_args = 1, .max_args = 1, .missing = "needs a scene",
                    .exits = "  0  rendered\n  1  an error, or a scene it does not support\n  2  bad command line\n"};
    int go = opt_run(&spec, argc, argv);
    a->scene_path = args[0];
    return go;
}

/* The scene, if it is one this reference renders: model instances and
 * point lights without attenuation.  NULL after saying why. */
static Scene *load_scene(const char *path)
{
    Err err;
    Scene *s;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    if (scene_load(path, &opt, 0, &s, &err)) {
        fprintf(stderr, "embree_ref: %s\n", err.msg);
        return NULL;
    }
    const char *why = s->sphere_count || s->plane_count || s->tri_count ? "only model instances are supported" : NULL;
    for (uint32_t i = 0; !why && i < s->light_count; i++)
        if (s->lights[i].kind != LIGHT_POINT || s->lights[i].attenuate)
            why = "only point lights without attenuation are supported";
    if (why) {
        fprintf(stderr, "embree_ref: %s: %s\n", path, why);
        scene_destroy(s);
        return NULL;
    }
    return s;
}

/* Every instance's triangles in world space, as one Embree mesh; its
 * vertex buffer (three vertices a triangle) into *vb. */
static RTCGeometry world_mesh(RTCDevice dev, const Scene *s, float **vb)
{
    uint64_t ntri = scene_triangle_count(s);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * ntri);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), ntri);
    uint64_t k = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const Instance *in = &s->instances[i];
        const Model *m = s->models[in->model];
        const mat3 rot = m3_rotation_xyz(in->rotate); /* as world_build turns it */
        for (uint32_t t = 0; t < m->tri_count; t++, k++)
            for (int c = 0; c < 3; c++) {
                vec3 w = v3_add(v3_scale(m3_apply(&rot, tri_vertex(&m->tris[t], c)), in->scale), in->translate);
                v[9 * k + 3 * c] = (float)w.x, v[9 * k + 3 * c + 1] = (float)w.y, v[9 * k + 3 * c + 2] = (float)w.z;
                ib[3 * k + c] = (unsigned)(3 * k + c);
            }
    }
    rtcCommitGeometry(g);
    *vb = v;
    return g;
}

/* The scene over g, built BUILDS + 1 times: the first, untimed, starts
 * Embree's threads; *build is the median of the rest, *tree_bytes what the
 * last one holds. */
static RTCScene build_scene(RTCDevice dev, RTCGeometry g, int robust, double *build, size_t *tree_bytes)
{
    double builds[BUILDS + 1];
    RTCScene rs = NULL;
    for (int b = 0; b <= BUILDS; b++) {
        if (rs)
            rtcReleaseScene(rs);
        rs = rtcNewScene(dev);
        if (robust)
            rtcSetSceneFlags(rs, RTC_SCENE_FLAG_ROBUST);
        rtcAttachGeometry(rs, g);
        long before = atomic_load(&device_bytes);
        double t0 = timer_now();
        rtcCommitScene(rs);
        builds[b] = timer_now() - t0;
        *tree_bytes = (size_t)(atomic_load(&device_bytes) - before);
    }
    qsort(builds + 1, BUILDS, sizeof *builds, cmp_double);
    *build = builds[1 + BUILDS / 2];
    return rs;
}

/* The frame, `repeat` times on `threads` threads: the best time, and the
 * last frame's ray counts. */
static double render_frames(Job *j, int threads, int repeat, unsigned long long *prim, unsigned long long *shad)
{
    double best = 1e30;
    pthread_t th[256];
    for (int f = 0; f < repeat; f++) {
        atomic_store(&j->next_line, 0);
        atomic_store(&j->primary, 0);
        atomic_store(&j->shadow, 0);
        double a = timer_now();
        for (int i = 0; i < threads; i++)
            pthread_create(&th[i], NULL, worker, j);
        for (int i = 0; i < threads; i++)
            pthread_join(th[i], NULL);
        double dt = timer_now() - a;
        if (dt < best)
            best = dt;
        *prim = atomic_load(&j->primary);
        *shad = atomic_load(&j->shadow);
    }
    return best;
}

int main(int argc, char **argv)
{
    Args a;
    int rc = parse_args(&a, argc, argv);
    if (rc != OPT_GO)
        return rc;
    Scene *s = load_scene(a.scene_path);
    if (!s)
        return 1;
    rc = 0;
    /* Embree builds and renders on the same number of threads as lanray:
     * its build runs on TBB, which the device config caps */
    char config[64];
    snprintf(config, sizeof config, "threads=%d,set_affinity=0", a.threads);
    RTCDevice dev = rtcNewDevice(config);
    if (!dev) {
        fprintf(stderr, "embree_ref: rtcNewDevice(\"%s\") failed\n", config);
        scene_destroy(s);
        return 1;
    }
    rtcSetDeviceMemoryMonitorFunction(dev, count_bytes, NULL);
    Job j = {.s = s, .cam = camera_frame(&s->camera, a.width, a.height)};
    float *vb;
    RTCGeometry g = world_mesh(dev, s, &vb);
    size_t buffers = (size_t)atomic_load(&device_bytes), tree_bytes = 0;
    double build;
    j.scene = build_scene(dev, g, a.robust, &build, &tree_bytes);
    rtcReleaseGeometry(g);
    j.vb = vb;
    j.pixels = malloc((size_t)a.width * a.height * 3);
    const Material *mat = s->instance_count && s->instances[0].material >= 0 ? &s->materials[s->instances[0].material]
                                                                             : &s->materials[0];
    j.kd = mat->kd, j.ks = mat->ks, j.shininess = mat->shininess;
    unsigned long long prim = 0, shad = 0, ntri = scene_triangle_count(s);
    double best = render_frames(&j, a.threads, a.repeat, &prim, &shad);
    printf("embree%s: %llu triangles, build %.3f s, memory %.1f bytes/triangle (tree %.1f + buffers %.1f); %dx%d threads %d: "
           "frame %.4f s, %.2f Mrays/s (%llu camera + %llu shadow rays)\n",
           a.robust ? " robust" : "", ntri, build, (double)(tree_bytes + buffers) / (double)ntri,
           (double)tree_bytes / (double)ntri, (double)buffers / (double)ntri, a.width, a.height, a.threads, best,
           (double)(prim + shad) / best * 1e-6, prim, shad);
    Err err;
    if (a.out && image_write(a.out, a.width, a.height, j.pixels, IMAGE_SRGB, &err)) {
        fprintf(stderr, "embree_ref: %s\n", err.msg);
        rc = 1;
    }
    free(j.pixels);
    rtcReleaseScene(j.scene);
    rtcReleaseDevice(dev);
    scene_destroy(s);
    return rc;
}

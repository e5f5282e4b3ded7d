/* rayclass - lanray and Intel Embree on the same rays, class by class, for
 * make bench (tools/bench/bench-rayclass).
 *
 *   rayclass [SCENE] [--width W] [--height H] [--threads T] [--repeat N]
 *            [--class C] [--mode M]
 *
 * SCENE is a scene file, a model (a preview scene, as lanray-render's), or
 * the built-in default scene without one (cli_open_scene).  From
 * lanray's camera rays (one through each pixel's centre) and their hits
 * it makes six sets of rays, each in the order lanray's renderer traces
 * them (neighbouring pixels side by side, eight to a packet):
 *   camera       the camera rays;
 *   point        a shadow ray from each hit to each point or spot light
 *                that faces it;
 *   area         shadow rays to 3 x 3 stratified points of an area light
 *                (the scene's first sphere light, seen as a disc, stopping
 *                at its lamp; in a scene without one, a disc about the
 *                first light a twentieth of its distance to the scene
 *                wide), point j of every pixel before point j + 1;
 *   reflection   each hit's mirror direction;
 *   refraction   each hit's refracted direction (glass of index 1.5;
 *                mirrored where that reflects totally);
 *   diffuse      a cosine-distributed direction about each hit's normal
 *                (numbers from the pixel), as a path's bounce.
 * Then it times each set through lanray as its renderer traces that
 * class (packets of eight: trace_closest_packet, trace_occluded_packet;
 * the diffuse bounces of eight paths in one call, trace_closest_each, as
 * the path integrator does: two walks side by side), one ray at a time
 * (trace_closest, trace_occluded) and by pairs, and through Embree
 * (rtcIntersect1 / rtcOccluded1, and packets of 4, 8 and 16 rays,
 * rtcIntersect4/8/16 / rtcOccluded4/8/16, with the coherent flag for camera
 * and shadow rays: on an AVX-512 CPU Embree's 16-ray packets are its
 * widest kernels, and on an Intel Xeon of 2026-11-28 they beat its 8-ray
 * ones on camera rays, its 4-ray ones every other mode on incoherent
 * rays): the same rays, T threads
 * each taking 64 rays at a time, best of N passes, the modes in turn pass
 * after pass, each timed pass after an untimed one of the same mode (the
 * 1M-triangle mesh's trees do not both fit the cache: the mode after
 * Embree's began with its nodes and leaves evicted, 4-5% slower, and
 * lanray's packets always came after Embree's).  --class and --mode time
 * one class or one mode alone (for perf or callgrind:
 * --toggle-collect=worker counts the tracing only, one pass a repeat).
 * Only tracing is timed, no shading.  Embree holds the same geometry:
 * every triangle in world space (one mesh), spheres as its sphere
 * primitive, a plane as two triangles 10^5 wide.  Each class's line says
 * how many rays agree (the same hit or miss and, for a hit, the same
 * distance within 10^-3 of it). */
#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <xmmintrin.h>

#include "app/cli.h"
#include "base/opt.h"
#include "base/sample.h"
#include "base/timer.h"
#include "geom/camera.h"
#include "scene/trace.h"
#include "shading/optics.h"

enum { CAMERA, POINT, AREA, REFLECTION, REFRACTION, DIFFUSE, CLASSES };
static const char *const class_names[CLASSES + 2] = {"camera", "point", "area", "reflection", "refraction", "diffuse",
                                                      "all", NULL};

/* One class's rays and what each tracer found. */
typedef struct {
    Ray *rays;
    real *tmax;     /* shadow rays' limits */
    float *t_ours;  /* closest: the hit's distance, or -1; shadow: 1 blocked, 0 clear */
    float *t_embree;
    size_t n, cap;
    int shadow, coherent;
} RaySet;

static void set_push(RaySet *s, Ray r, real tmax)
{
    if (s->n == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 4096;
        s->rays = realloc(s->rays, s->cap * sizeof *s->rays);
        s->tmax = realloc(s->tmax, s->cap * sizeof *s->tmax);
        if (!s->rays || !s->tmax) {
            fprintf(stderr, "rayclass: out of memory\n");
            exit(1);
        }
    }
    s->rays[s->n] = r;
    s->tmax[s->n++] = tmax;
}

/* What the rays are made from: the camera ray's hit of each pixel. */
typedef struct {
    int hit;
    Surface sf;
    vec3 d;
} PixelHit;

/* The area light the area class samples: a disc (centre, radius) facing
 * each point, and the lamp sphere the rays stop at (lamp_r 0: none). */
typedef struct {
    vec3 centre;
    real radius, lamp_r;
} AreaDisc;

static AreaDisc area_disc(const World *w)
{
    for (uint32_t i = 0; i < w->light_count; i++)
        if (w->lights[i].kind == LIGHT_SPHERE)
            return (AreaDisc){w->lights[i].pos, w->lights[i].radius, w->lights[i].lamp_count ? w->lights[i].radius : 0};
    Aabb b = w->tree->node_count ? (Aabb){v3(w->tree->nodes[0].bmin[0], w->tree->nodes[0].bmin[1], w->tree->nodes[0].bmin[2]),
                                          v3(w->tree->nodes[0].bmax[0], w->tree->nodes[0].bmax[1], w->tree->nodes[0].bmax[2])}
                                 : (Aabb){v3_splat(0), v3_splat(0)};
    vec3 c = v3_scale(v3_add(b.min, b.max), R(0.5)), at = w->light_count ? w->lights[0].pos : v3(0, 10, 0);
    return (AreaDisc){at, v3_len(v3_sub(at, c)) / R(20), 0};
}

/* A shadow ray from the hit towards point `to`, stopping short of it (or
 * of the lamp sphere about `lamp`, lamp_r wide); 0 where the point is
 * behind the surface. */
static int shadow_to(const PixelHit *h, vec3 to, vec3 lamp, real lamp_r, Ray *out, real *tmax)
{
    vec3 L = v3_sub(to, h->sf.p);
    real dist = v3_len(L);
    if (!(dist > R(0)))
        return 0;
    L = v3_scale(L, R(1) / dist);
    if (!(v3_dot(h->sf.ns, L) > R(0)))
        return 0;
    vec3 org = trace_offset_origin(h->sf.ps, h->sf.ng, h->sf.ps_err);
    *out = ray_make(org, L, R(0), REAL_INF);
    real t = dist, tl;
    if (lamp_r > R(0) && sphere_intersect(out, lamp, lamp_r, REAL_INF, &tl) && tl < t)
        t = tl;
    *tmax = t * (R(1) - R(1e-4));
    return 1;
}

/* The secondary rays of one hit: mirrored, refracted, a diffuse bounce. */
static void secondary_rays(RaySet *sets, const PixelHit *h, uint32_t pixel)
{
    const Surface *sf = &h->sf;
    vec3 front = trace_offset_origin(sf->p, sf->ng, sf->err), back = trace_offset_origin(sf->p, v3_neg(sf->ng), sf->err);
    vec3 r = optics_reflect(h->d, sf->ns);
    if (!(v3_dot(r, sf->ng) > R(0)))
        r = optics_reflect(h->d, sf->ng);
    set_push(&sets[REFLECTION], ray_make(front, v3_norm(r), R(0), REAL_INF), REAL_INF);
    vec3 t;
    if (optics_refract(h->d, sf->ns, R(1) / R(1.5), &t) && v3_dot(t, sf->ng) < R(0))
        set_push(&sets[REFRACTION], ray_make(back, v3_norm(t), R(0), REAL_INF), REAL_INF);
    else
        set_push(&sets[REFRACTION], ray_make(front, v3_norm(r), R(0), REAL_INF), REAL_INF);
    /* cosine-distributed: a uniform point of the disc lifted onto the hemisphere */
    uint32_t key = sample_hash(pixel * 2654435761u + 12345u);
    real x, y;
    sample_disc(sample_unit(key), sample_unit(sample_hash(key)), &x, &y);
    vec3 a, b;
    v3_frame(sf->ns, &a, &b);
    vec3 d = v3_add(v3_add(v3_scale(a, x), v3_scale(b, y)), v3_scale(sf->ns, sqrt(real_max(R(0), R(1) - x * x - y * y))));
    set_push(&sets[DIFFUSE], ray_make(front, v3_norm(d), R(0), REAL_INF), REAL_INF);
}

/* Every class's rays, from the camera rays of a w x h frame. */
static void make_rays(const World *w, int width, int height, RaySet *sets)
{
    CameraFrame cam = camera_frame(&w->view.camera, width, height);
    size_t np = (size_t)width * (size_t)height;
    PixelHit *px = calloc(np, sizeof *px);
    if (!px)
        exit(1);
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++) {
            vec3 org, d;
            camera_ray(&cam, (real)x + R(0.5), (real)y + R(0.5), &org, &d);
            Ray r = ray_make(org, v3_norm(d), R(0), REAL_INF);
            set_push(&sets[CAMERA], r, REAL_INF);
            PixelHit *h = &px[(size_t)y * (size_t)width + (size_t)x];
            Hit hit;
            h->d = r.dir;
            if ((h->hit = trace_closest(w, &r, &hit)))
                trace_surface(w, &r, &hit, &h->sf);
        }
    for (uint32_t l = 0; l < w->light_count; l++)
        if (w->lights[l].kind == LIGHT_POINT || w->lights[l].kind == LIGHT_SPOT)
            for (size_t i = 0; i < np; i++) {
                Ray r;
                real tm;
                if (px[i].hit && shadow_to(&px[i], w->lights[l].pos, v3_splat(0), 0, &r, &tm))
                    set_push(&sets[POINT], r, tm);
            }
    AreaDisc disc = area_disc(w);
    for (uint32_t j = 0; j < 9; j++)
        for (size_t i = 0; i < np; i++) {
            if (!px[i].hit)
                continue;
            real u, v, x, y, tm;
            sample_stratum(sample_hash((uint32_t)i), j, 3, &u, &v);
            sample_disc(u, v, &x, &y);
            vec3 a, b;
            v3_frame(v3_norm(v3_sub(px[i].sf.p, disc.centre)), &a, &b);
            vec3 to = v3_add(disc.centre, v3_scale(v3_add(v3_scale(a, x), v3_scale(b, y)), disc.radius));
            Ray r;
            if (shadow_to(&px[i], to, disc.centre, disc.lamp_r, &r, &tm))
                set_push(&sets[AREA], r, tm);
        }
    for (size_t i = 0; i < np; i++)
        if (px[i].hit)
            secondary_rays(sets, &px[i], (uint32_t)i);
    free(px);
}

/* Embree's scene of the world's geometry; NULL after saying why. */
static RTCScene embree_scene(RTCDevice dev, const World *w)
{
    RTCScene es = rtcNewScene(dev);
    uint64_t ntri = w->tri_count + 2u * w->plane_count;
    for (uint32_t i = 0; i < w->instance_count; i++)
        ntri += w->models[w->instances[i].model]->tri_count;
    if (ntri) {
        RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * ntri);
        unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), ntri);
        uint64_t k = 0;
        vec3 tv[3];
#define PUT_TRI()                                                                                                    \
    do {                                                                                                             \
        for (int c = 0; c < 3; c++) {                                                                                \
            v[9 * k + 3 * c] = (float)tv[c].x, v[9 * k + 3 * c + 1] = (float)tv[c].y, v[9 * k + 3 * c + 2] = (float)tv[c].z; \
            ib[3 * k + c] = (unsigned)(3 * k + c);                                                                   \
        }                                                                                                            \
        k++;                                                                                                         \
    } while (0)
        for (uint32_t t = 0; t < w->tri_count; t++) {
            for (int c = 0; c < 3; c++)
                tv[c] = tri_vertex(&w->tris[t], c);
            PUT_TRI();
        }
        for (uint32_t i = 0; i < w->instance_count; i++) {
            const WorldInstance *in = &w->instances[i];
            const Model *m = w->models[in->model];
            for (uint32_t t = 0; t < m->tri_count; t++) {
                for (int c = 0; c < 3; c++)
                    tv[c] = v3_add(v3_scale(m3_apply(&in->rot, tri_vertex(&m->tris[t], c)), in->scale), in->translate);
                PUT_TRI();
            }
        }
        for (uint32_t i = 0; i < w->plane_count; i++) { /* a square 10^5 wide about the plane's point */
            vec3 a, b, p = w->planes[i].point;
            v3_frame(w->planes[i].unit, &a, &b);
            a = v3_scale(a, R(1e5)), b = v3_scale(b, R(1e5));
            vec3 q[4] = {v3_sub(v3_sub(p, a), b), v3_sub(v3_add(p, a), b), v3_add(v3_add(p, a), b), v3_add(v3_sub(p, a), b)};
            tv[0] = q[0], tv[1] = q[1], tv[2] = q[2];
            PUT_TRI();
            tv[0] = q[0], tv[1] = q[2], tv[2] = q[3];
            PUT_TRI();
        }
#undef PUT_TRI
        rtcCommitGeometry(g);
        rtcAttachGeometry(es, g);
        rtcReleaseGeometry(g);
    }
    if (w->sphere_count) {
        RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), w->sphere_count);
        for (uint32_t i = 0; i < w->sphere_count; i++) {
            const Sphere *sp = &w->spheres[i];
            v[4 * i] = (float)sp->centre.x, v[4 * i + 1] = (float)sp->centre.y, v[4 * i + 2] = (float)sp->centre.z;
            v[4 * i + 3] = (float)sp->radius;
        }
        rtcCommitGeometry(g);
        rtcAttachGeometry(es, g);
        rtcReleaseGeometry(g);
    }
    rtcCommitScene(es);
    return es;
}

/* How a set is traced. */
typedef enum { OURS_PACKET, OURS_SINGLE, OURS_PAIRS, EMBREE_1, EMBREE_4, EMBREE_8, EMBREE_16, MODES } Mode;
static const char *const mode_names[MODES + 2] = {"lanray8", "lanray1", "lanray2", "embree1", "embree4", "embree8", "embree16", "all", NULL};

typedef struct {
    const World *w;
    RTCScene es;
    RaySet *set;
    Mode mode;
    atomic_size_t next;
} Job;

#define CHUNK 64

static void embree_ray(const Ray *r, real tmax, struct RTCRay *e)
{
    e->org_x = (float)r->org.x, e->org_y = (float)r->org.y, e->org_z = (float)r->org.z;
    e->dir_x = (float)r->dir.x, e->dir_y = (float)r->dir.y, e->dir_z = (float)r->dir.z;
    e->tnear = 0, e->tfar = (float)tmax, e->time = 0, e->mask = 0xffffffffu, e->id = 0, e->flags = 0;
}

/* Rays [i, i + n) of the set through Embree one by one (n <= 8). */
static void embree_trace1(const Job *j, struct RTCIntersectContext *ctx, size_t i, int n)
{
    RaySet *s = j->set;
    for (int k = 0; k < n; k++) {
        struct RTCRayHit rh;
        embree_ray(&s->rays[i + k], s->tmax[i + k], &rh.ray);
        if (s->shadow) {
            rtcOccluded1(j->es, ctx, &rh.ray);
            s->t_embree[i + k] = rh.ray.tfar < 0 ? 1.0f : 0.0f;
        } else {
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID, rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(j->es, ctx, &rh);
            s->t_embree[i + k] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1.0f : rh.ray.tfar;
        }
    }
}

/* Rays [i, i + n) of the set (n <= W) through Embree as one packet of W
 * (4, 8 or 16): its RTCRayHitW is the same layout at every width. */
#define EMBREE_PACKET(W)                                                                                          \
    static void embree_trace##W(const Job *j, struct RTCIntersectContext *ctx, size_t i, int n)                   \
    {                                                                                                             \
        RaySet *s = j->set;                                                                                       \
        struct RTCRayHit##W rh __attribute__((aligned(64)));                                                     \
        int valid[W] __attribute__((aligned(64))); /* Embree reads it as a vector */                          \
        for (int k = 0; k < W; k++) {                                                                             \
            struct RTCRay e;                                                                                      \
            valid[k] = k < n ? -1 : 0;                                                                            \
            embree_ray(&s->rays[i + (k < n ? k : 0)], s->tmax[i + (k < n ? k : 0)], &e);                          \
            rh.ray.org_x[k] = e.org_x, rh.ray.org_y[k] = e.org_y, rh.ray.org_z[k] = e.org_z;                      \
            rh.ray.dir_x[k] = e.dir_x, rh.ray.dir_y[k] = e.dir_y, rh.ray.dir_z[k] = e.dir_z;                      \
            rh.ray.tnear[k] = 0, rh.ray.tfar[k] = e.tfar, rh.ray.time[k] = 0, rh.ray.mask[k] = ~0u;               \
            rh.ray.id[k] = 0, rh.ray.flags[k] = 0;                                                                \
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID, rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;            \
        }                                                                                                         \
        if (s->shadow) {                                                                                          \
            rtcOccluded##W(valid, j->es, ctx, &rh.ray);                                                           \
            for (int k = 0; k < n; k++)                                                                           \
                s->t_embree[i + k] = rh.ray.tfar[k] < 0 ? 1.0f : 0.0f;                                            \
        } else {                                                                                                  \
            rtcIntersect##W(valid, j->es, ctx, &rh);                                                              \
            for (int k = 0; k < n; k++)                                                                           \
                s->t_embree[i + k] = rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID ? -1.0f : rh.ray.tfar[k];        \
        }                                                                                                         \
    }
EMBREE_PACKET(4)
EMBREE_PACKET(8)
EMBREE_PACKET(16)

/* Rays [i, i + n) of the set (n <= 8) through lanray: as a packet, one
 * by one, or by pairs (closest hits: trace_closest_each, two walks side
 * by side, as the path integrator traces its live paths' bounces; shadow
 * rays one by one). */
static void ours_trace(const Job *j, size_t i, int n, Mode mode)
{
    const int packet = mode == OURS_PACKET;
    RaySet *s = j->set;
    if (s->shadow) {
        uint32_t b = 0;
        if (packet)
            b = trace_occluded_packet(j->w, &s->rays[i], n, &s->tmax[i], NULL);
        else
            for (int k = 0; k < n; k++)
                b |= (uint32_t)trace_occluded(j->w, &s->rays[i + k], s->tmax[i + k], NULL) << k;
        for (int k = 0; k < n; k++)
            s->t_ours[i + k] = (float)(b >> k & 1);
        return;
    }
    Hit h[TRACE_PACKET];
    if (packet && s->coherent) /* camera rays */
        trace_closest_packet(j->w, &s->rays[i], n, h);
    else if (packet) /* as shading sends on what mirrors and glass (and a diffuse bounce) send */
        trace_closest_bounced(j->w, &s->rays[i], n, h);
    else if (mode == OURS_PAIRS) /* as the path integrator traces its live paths' bounces */
        trace_closest_each(j->w, &s->rays[i], n, h);
    else
        for (int k = 0; k < n; k++)
            trace_closest(j->w, &s->rays[i + k], &h[k]);
    for (int k = 0; k < n; k++)
        s->t_ours[i + k] = h[k].kind == HIT_NONE ? -1.0f : (float)h[k].t;
}

static void *worker(void *arg)
{
    Job *j = arg;
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON); /* as Embree advises for its kernels */
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = j->set->coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    size_t i, n = j->set->n;
    while ((i = atomic_fetch_add(&j->next, CHUNK)) < n) {
        size_t end = i + CHUNK < n ? i + CHUNK : n;
        /* a packet mode's own width; lanray's and single rays by eight */
        const size_t step = j->mode == EMBREE_16 ? 16 : j->mode == EMBREE_4 ? 4 : 8;
        for (size_t p = i; p < end; p += step) {
            int m = end - p < step ? (int)(end - p) : (int)step;
            if (j->mode == OURS_PACKET || j->mode == OURS_SINGLE || j->mode == OURS_PAIRS)
                ours_trace(j, p, m, j->mode);
            else if (j->mode == EMBREE_1)
                embree_trace1(j, &ctx, p, m);
            else if (j->mode == EMBREE_4)
                embree_trace4(j, &ctx, p, m);
            else if (j->mode == EMBREE_8)
                embree_trace8(j, &ctx, p, m);
            else
                embree_trace16(j, &ctx, p, m);
        }
    }
    return NULL;
}

/* The time of one pass over the set in mode m on `threads` threads. */
static double time_pass(Job *j, Mode m, int threads)
{
    pthread_t th[256];
    j->mode = m;
    atomic_store(&j->next, 0);
    double t0 = timer_now();
    for (int i = 0; i < threads; i++)
        pthread_create(&th[i], NULL, worker, j);
    for (int i = 0; i < threads; i++)
        pthread_join(th[i], NULL);
    return timer_now() - t0;
}

/* Rays on which the two found the same: hit or miss (blocked or not) and the distance within 10^-3 of it. */
static double agreement(const RaySet *s)
{
    size_t same = 0;
    for (size_t i = 0; i < s->n; i++) {
        float a = s->t_ours[i], b = s->t_embree[i];
        same += (a < 0 && b < 0) || (a >= 0 && b >= 0 && fabsf(a - b) <= 1e-3f * fmaxf(1.0f, fabsf(a)));
    }
    return s->n ? 100.0 * (double)same / (double)s->n : 100.0;
}

typedef struct {
    const char *scene_path;
    int width, height, threads, repeat;
    int only;      /* a class, or CLASSES: all */
    int only_mode; /* a mode, or MODES: all */
} Args;

static int parse_args(Args *a, int argc, char **argv)
{
    *a = (Args){.width = 1024, .height = 768, .threads = 1, .repeat = 3, .only = CLASSES, .only_mode = MODES};
    const Opt opts[] = {
        {.name = "--width", .kind = OPT_INT, .dst = &a->width, .arg = "W", .lo = 1, .hi = 8192, .help = "frame width"},
        {.name = "--height", .kind = OPT_INT, .dst = &a->height, .arg = "H", .lo = 1, .hi = 8192, .help = "frame height"},
        {.name = "--threads", .kind = OPT_INT, .dst = &a->threads, .arg = "T", .lo = 1, .hi = 256, .help = "threads"},
        {.name = "--repeat", .kind = OPT_INT, .dst = &a->repeat, .arg = "N", .lo = 1, .hi = 1000,
         .help = "passes over each set, the best timed"},
        {.name = "--class", .kind = OPT_CHOICE, .dst = &a->only, .choices = class_names,
         .help = "time this class alone (for a profiler), or all"},
        {.name = "--mode", .kind = OPT_CHOICE, .dst = &a->only_mode, .choices = mode_names,
         .help = "trace with this mode alone (for a profiler; the others print 0), or all"},
        {0},
    };
    const char *args[1] = {NULL};
    OptSpec spec = {.prog = "rayclass", .synopsis = "[SCENE] [options]",
                    .about = "Times lanray and Intel Embree on the same rays, class by class (camera, shadow rays to\n"
                             "point and area lights, reflected, refracted, diffuse bounces): make bench.",
                    .opts = opts, .args = args, .min_args = 0, .max_args = 1, .missing = "",
                    .exits = "  0  measured\n  1  an error\n  2  bad command line\n"};
    int go = opt_run(&spec, argc, argv);
    a->scene_path = args[0];
    return go;
}

/* Times every class and prints a line for each. */
static void measure(const World *w, RTCScene es, RaySet *sets, const Args *a)
{
    for (int c = 0; c < CLASSES; c++) {
        if (a->only != CLASSES && c != a->only)
            continue;
        RaySet *s = &sets[c];
        s->shadow = c == POINT || c == AREA;
        s->coherent = c == CAMERA || s->shadow;
        s->t_ours = malloc((s->n + 1) * sizeof(float));
        s->t_embree = malloc((s->n + 1) * sizeof(float));
        Job j = {.w = w, .es = es, .set = s};
        /* the modes in turn, pass after pass, so that a slow spell of this
         * shared machine falls on all of them alike */
        double t[MODES];
        for (int m = 0; m < MODES; m++)
            t[m] = 1e30;
        for (int r = 0; r < a->repeat && s->n; r++)
            for (int m = 0; m < MODES; m++)
                if (a->only_mode == MODES || m == a->only_mode) {
                    if (a->only_mode == MODES) /* the caches warmed with this mode's tree (alone, it stays) */
                        time_pass(&j, (Mode)m, a->threads);
                    t[m] = fmin(t[m], time_pass(&j, (Mode)m, a->threads));
                }
        /* the renderer's way: packets, but a path's diffuse bounces by pairs */
        Mode ours = c == DIFFUSE ? OURS_PAIRS : OURS_PACKET;
        j.mode = ours; /* the results compared: the renderer's way against rtcIntersect1 */
        printf("class %s rays %zu threads %d", class_names[c], s->n, a->threads);
        for (int m = 0; m < MODES; m++)
            printf(" %s %.3f", mode_names[m], s->n ? (double)s->n / t[m] * 1e-6 : 0.0);
        if (a->only_mode == MODES) {
            time_pass(&j, ours, 1);
            time_pass(&j, EMBREE_1, 1);
            printf(" ours %s agree %.4f\n", mode_names[ours], agreement(s));
        } else {
            printf(" ours %s agree -\n", mode_names[ours]);
        }
        free(s->t_ours), free(s->t_embree);
    }
}

int main(int argc, char **argv)
{
    Args a;
    int rc = parse_args(&a, argc, argv);
    if (rc != OPT_GO)
        return rc;
    Err err;
    Scene *s = NULL;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    if (cli_open_scene(a.scene_path, &opt, 0, 0, &s, &err)) {
        fprintf(stderr, "rayclass: %s\n", err.msg);
        return 1;
    }
    World *w = world_build(s, NULL, &err);
    if (!w) {
        fprintf(stderr, "rayclass: %s\n", err.msg);
        scene_destroy(s);
        return 1;
    }
    char config[64];
    snprintf(config, sizeof config, "threads=%d,set_affinity=0", a.threads);
    RTCDevice dev = rtcNewDevice(config);
    RTCScene es = dev ? embree_scene(dev, w) : NULL;
    if (!es) {
        fprintf(stderr, "rayclass: Embree's device or scene failed\n");
        return 1;
    }
    RaySet sets[CLASSES] = {0};
    make_rays(w, a.width, a.height, sets);
    measure(w, es, sets, &a);
    for (int c = 0; c < CLASSES; c++)
        free(sets[c].rays), free(sets[c].tmax);
    rtcReleaseScene(es);
    rtcReleaseDevice(dev);
    world_destroy(w);
    scene_destroy(s);
    return 0;
}

/* camera_path.c - see camera_path.h. */
#include "scene/camera_path.h"

#include "base/dmath.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/array.h"
#include "base/fileio.h"
#include "base/lex.h"
#include "scene/scene_fields.h"

static int fail(Err *err, const char *name, int line, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static int fail(Err *err, const char *name, int line, const char *fmt, ...)
{
    char what[384];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return err_set(err, "%s:%d: %s", name, line, what);
}

/* Whether two keys can be interpolated: the same projection, a lens on both or neither. */
static const char *keys_mismatch(const Camera *a, const Camera *b)
{
    if (a->kind != b->kind)
        return "a key of another projection than the one before (a path keeps one)";
    if ((a->aperture > R(0)) != (b->aperture > R(0)))
        return "a lens on one key and not on the one before (give every key an aperture, or none)";
    return NULL;
}

/* One `key TIME CAMERA-KEYS` line into *k. */
static int read_key(const Tokens *t, const char *name, int line, real prev_t, int first, PathKey *k, Err *err)
{
    if (strcmp(t->tok[0], "key") != 0)
        return fail(err, name, line, "unknown directive '%s' (a path has 'key TIME camera-keys' lines)", t->tok[0]);
    if (t->n < 2 || lex_real(t->tok[1], &k->t) || !(k->t >= R(0)))
        return fail(err, name, line, "'key' expects a time in seconds (a finite number >= 0) first");
    if (!first && !(k->t > prev_t))
        return fail(err, name, line, "key at %g s is not after the key before it (%g s)", (double)k->t, (double)prev_t);
    CameraSpec sp;
    FieldSet given;
    const char *names[FIELD_MAX];
    char at[512];
    memset(&sp, 0, sizeof sp);
    field_defaults(&camera_kind, &sp, sizeof sp, 0);
    snprintf(at, sizeof at, "%s:%d", name, line);
    if (field_read(&camera_kind, t, 2, 0, &sp, &given, names, at, err))
        return -1;
    if (scene_fields_finish_camera(&sp, given))
        return fail(err, name, line, "camera 'lookat' point equals its position");
    char why[160];
    if (camera_problem(&sp.cam, why, sizeof why))
        return fail(err, name, line, "%s", why);
    k->cam = sp.cam;
    return 0;
}

int camera_path_parse(char *text, size_t len, const char *name, CameraPath *out, Err *err)
{
    memset(out, 0, sizeof *out);
    uint32_t cap = 0;
    Lexer lx = lex_make(text, len);
    Tokens t;
    while (lex_next_line(&lx, &t)) {
        if (t.n == 0)
            continue;
        if (t.truncated)
            return camera_path_free(out), fail(err, name, lx.line, "line has more than 256 words");
        if (array_reserve((void **)&out->keys, &cap, out->count + 1, sizeof *out->keys, CAMERA_PATH_MAX_KEYS))
            return camera_path_free(out), fail(err, name, lx.line, "more than %u keys, or out of memory", CAMERA_PATH_MAX_KEYS);
        PathKey *k = &out->keys[out->count];
        const PathKey *prev = out->count ? k - 1 : NULL;
        if (read_key(&t, name, lx.line, prev ? prev->t : 0, !prev, k, err))
            return camera_path_free(out), -1;
        const char *why = prev ? keys_mismatch(&prev->cam, &k->cam) : NULL;
        if (why)
            return camera_path_free(out), fail(err, name, lx.line, "%s", why);
        out->count++;
    }
    if (out->count == 0)
        return err_set(err, "%s: no camera keys (lines 'key TIME position X Y Z ...')", name);
    /* yaw the short way round: each key within half a turn of the one before */
    for (uint32_t i = 1; i < out->count; i++) {
        real *y = &out->keys[i].cam.yaw, y0 = out->keys[i - 1].cam.yaw;
        *y = y0 + (real)remainder((double)(*y - y0), 360.0);
    }
    return 0;
}

int camera_path_load(const char *path, CameraPath *out, Err *err)
{
    char *text;
    size_t len;
    memset(out, 0, sizeof *out);
    if (file_read_all(path, CAMERA_PATH_MAX_BYTES, &text, &len, err))
        return -1;
    int rc = camera_path_parse(text, len, path, out, err);
    free(text);
    return rc;
}

void camera_path_free(CameraPath *p)
{
    free(p->keys);
    memset(p, 0, sizeof *p);
}

real camera_path_end(const CameraPath *p) { return p->count ? p->keys[p->count - 1].t : R(0); }

/* Catmull-Rom through a, b (u = 0), c (u = 1), d. */
static real spline(real a, real b, real c, real d, real u)
{
    return b + R(0.5) * u * ((c - a) + u * ((R(2) * a - R(5) * b + R(4) * c - d) + u * (R(3) * (b - c) + d - a)));
}

static vec3 spline3(vec3 a, vec3 b, vec3 c, vec3 d, real u)
{
    return v3(spline(a.x, b.x, c.x, d.x, u), spline(a.y, b.y, c.y, d.y, u), spline(a.z, b.z, c.z, d.z, u));
}

static real lerp(real a, real b, real u) { return a + (b - a) * u; }

Camera camera_path_at(const CameraPath *p, real t)
{
    const uint32_t n = p->count;
    if (t <= p->keys[0].t || n == 1)
        return p->keys[0].cam;
    if (t >= p->keys[n - 1].t)
        return p->keys[n - 1].cam;
    uint32_t lo = 0, hi = n - 1; /* keys[lo].t <= t < keys[hi].t */
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (p->keys[mid].t <= t)
            lo = mid;
        else
            hi = mid;
    }
    const Camera *a = &p->keys[lo ? lo - 1 : 0].cam, *b = &p->keys[lo].cam, *c = &p->keys[hi].cam,
                 *d = &p->keys[hi + 1 < n ? hi + 1 : hi].cam;
    const real u = (t - p->keys[lo].t) / (p->keys[hi].t - p->keys[lo].t);
    Camera out = *b;
    out.pos = spline3(a->pos, b->pos, c->pos, d->pos, u);
    out.yaw = spline(a->yaw, b->yaw, c->yaw, d->yaw, u);
    out.pitch = spline(a->pitch, b->pitch, c->pitch, d->pitch, u);
    out.roll = spline(a->roll, b->roll, c->roll, d->roll, u);
    out.zoom = b->zoom * (real)dmath_pow((double)(c->zoom / b->zoom), (double)u);
    out.size = lerp(b->size, c->size, u);
    out.fov = lerp(b->fov, c->fov, u);
    out.aperture = lerp(b->aperture, c->aperture, u);
    out.focus = lerp(b->focus, c->focus, u);
    /* keys near the range of the numbers can overflow between them: the
     * camera then holds the key's (every camera a path gives is valid) */
    char why[160];
    return camera_problem(&out, why, sizeof why) ? *b : out;
}

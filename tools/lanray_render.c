/* lanray-render - the standalone renderer.
 *
 *   lanray-render [scene] [-o out.png|out.ppm] [--width W] [--height H]
 *                 [--aa N | --aa adaptive[:N]] [--threads T] [--bvh sbt|mst|sah]
 *                 [--shading phong|diffuse] [--shadows on|off]
 *                 [--filter nearest|bilinear] [--frames N] [--quiet]
 *
 * Without a scene file it renders the built-in default scene.  Prints the
 * frame time and rays per second (camera rays plus shadow rays). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image.h"
#include "render.h"
#include "scene_default.h"
#include "scene_parse.h"
#include "timer.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: lanray-render [scene] [options]\n"
            "  -o FILE              output image, .png or .ppm (default lanray.png)\n"
            "  --width W --height H frame size (default 1024x768)\n"
            "  --aa N               N x N samples per pixel, N = 1..16\n"
            "  --aa adaptive[:N]    one sample, N x N (default 4) where neighbours differ\n"
            "  --threads T          worker threads (default: all cores)\n"
            "  --bvh sbt|mst|sah    BVH builder for models (default sah; forces a rebuild of .tmd models)\n"
            "  --shading phong|diffuse, --shadows on|off, --filter nearest|bilinear\n"
            "  --frames N           render N times, report the best and mean frame time\n"
            "  --segment N          render the frame as segments of N lines, one after another\n"
            "  --profile FILE       also time every line alone and write 'line,microseconds' to FILE\n"
            "  --quiet              print only the timing line\n");
}

static int parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || *end || v < lo || v > hi)
        return -1;
    *out = (int)v;
    return 0;
}

typedef struct {
    int aa, adaptive, shading, shadows, filter; /* -1: keep the scene's value */
} Overrides;

int main(int argc, char **argv)
{
    const char *scene_path = NULL, *out = "lanray.png", *profile = NULL;
    int width = 1024, height = 768, frames = 1, quiet = 0, force_bvh = 0, segment = 0;
    int threads = (int)sysconf(_SC_NPROCESSORS_ONLN);
    if (threads < 1)
        threads = 1;
    BvhOptions bvh = bvh_options_default(BVH_SAH);
    Overrides ov = {-1, -1, -1, -1, -1};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int bad = 0;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--quiet") == 0) {
            quiet = 1;
            continue;
        } else if (a[0] != '-') {
            if (scene_path) {
                fprintf(stderr, "lanray-render: more than one scene given ('%s' and '%s')\n", scene_path, a);
                return 2;
            }
            scene_path = a;
            continue;
        } else if (!v) {
            fprintf(stderr, "lanray-render: option '%s' needs a value\n", a);
            usage(stderr);
            return 2;
        } else if (strcmp(a, "-o") == 0) {
            out = v;
        } else if (strcmp(a, "--profile") == 0) {
            profile = v;
        } else if (strcmp(a, "--width") == 0) {
            bad = parse_int(v, 1, RENDER_MAX_SIDE, &width);
        } else if (strcmp(a, "--height") == 0) {
            bad = parse_int(v, 1, RENDER_MAX_SIDE, &height);
        } else if (strcmp(a, "--threads") == 0) {
            bad = parse_int(v, 1, RENDER_MAX_THREADS, &threads);
        } else if (strcmp(a, "--frames") == 0) {
            bad = parse_int(v, 1, 100000, &frames);
        } else if (strcmp(a, "--segment") == 0) {
            bad = parse_int(v, 1, RENDER_MAX_SIDE, &segment);
        } else if (strcmp(a, "--aa") == 0) {
            if (strncmp(v, "adaptive", 8) == 0) {
                ov.adaptive = 1;
                ov.aa = 4;
                bad = v[8] == ':' ? parse_int(v + 9, 1, AA_MAX, &ov.aa) : v[8] != 0;
            } else {
                ov.adaptive = 0;
                bad = parse_int(v, 1, AA_MAX, &ov.aa);
            }
        } else if (strcmp(a, "--bvh") == 0) {
            bad = bvh_kind_parse(v, &bvh.kind);
            force_bvh = 1;
        } else if (strcmp(a, "--shading") == 0) {
            ov.shading = strcmp(v, "phong") == 0 ? SHADE_PHONG : strcmp(v, "diffuse") == 0 ? SHADE_DIFFUSE : -2;
            bad = ov.shading == -2;
        } else if (strcmp(a, "--shadows") == 0) {
            ov.shadows = strcmp(v, "on") == 0 ? 1 : strcmp(v, "off") == 0 ? 0 : -2;
            bad = ov.shadows == -2;
        } else if (strcmp(a, "--filter") == 0) {
            ov.filter = strcmp(v, "nearest") == 0 ? FILTER_NEAREST : strcmp(v, "bilinear") == 0 ? FILTER_BILINEAR : -2;
            bad = ov.filter == -2;
        } else {
            fprintf(stderr, "lanray-render: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        }
        if (bad) {
            fprintf(stderr, "lanray-render: bad value '%s' for %s\n", v, a);
            return 2;
        }
        i++;
    }
    Err err = {{0}};
    Scene *scene;
    double t0 = timer_now();
    int rc = scene_path ? scene_load(scene_path, &bvh, force_bvh, &scene, &err) : scene_default(&scene, &bvh, &err);
    if (rc) {
        fprintf(stderr, "lanray-render: %s\n", err.msg);
        return 1;
    }
    RenderSettings *rs = &scene->settings;
    if (ov.aa >= 0)
        rs->aa = ov.aa, rs->adaptive = ov.adaptive;
    if (ov.shading >= 0)
        rs->shading = (ShadeModel)ov.shading;
    if (ov.shadows >= 0)
        rs->shadows = ov.shadows;
    if (ov.filter >= 0)
        rs->filter = (TextureFilter)ov.filter;
    if (scene_prepare(scene, &err)) {
        fprintf(stderr, "lanray-render: %s\n", err.msg);
        scene_destroy(scene);
        return 1;
    }
    double t1 = timer_now();
    RenderPool *pool = render_pool_create(threads, &err);
    uint8_t *pixels = malloc((size_t)width * (size_t)height * 3);
    if (!pool || !pixels) {
        fprintf(stderr, "lanray-render: %s\n", pool ? "out of memory for the frame" : err.msg);
        free(pixels);
        render_pool_destroy(pool);
        scene_destroy(scene);
        return 1;
    }
    if (!quiet)
        printf("scene: %s, %llu triangles, %u spheres, %u planes, %u lights; loaded in %.3f s\n",
               scene_path ? scene_path : "built-in default", (unsigned long long)scene_triangle_count(scene),
               scene->sphere_count, scene->plane_count, scene->light_count, t1 - t0);
    double best = 1e30, sum = 0;
    RayStats st = {0, 0};
    for (int f = 0; f < frames && rc == 0; f++) {
        double a = timer_now();
        int seg = segment ? segment : height;
        st = (RayStats){0, 0};
        for (int y = 0; rc == 0 && y < height; y += seg) {
            RayStats part;
            rc = render_lines(pool, scene, width, height, y, y + seg <= height ? seg : height - y,
                              pixels + (size_t)y * width * 3, &part, &err);
            st.primary += part.primary;
            st.shadow += part.shadow;
        }
        double dt = timer_now() - a;
        sum += dt;
        if (dt < best)
            best = dt;
    }
    if (rc == 0 && profile) {
        /* Per-line cost, for the scheduler simulator (tools/schedsim): the
         * pure rendering work of every line.  The frame is rendered line by
         * line, top to bottom, PROFILE_PASSES times; each line keeps its
         * fastest pass, because interference only ever adds time.  Passes
         * run in frame order, as a client renders a segment: timing one line
         * several times in a row would find its geometry in the cache and
         * make the costly lines look cheaper than they are inside a segment.
         * A call into the pool costs a hand-off when the pool has worker
         * threads; the simulator models it as the per-segment overhead, so
         * it is measured on a one-pixel call and taken off. */
        enum { PROFILE_PASSES = 15, PROFILE_CALLS = 64 };
        FILE *pf = fopen(profile, "w");
        double *line = calloc((size_t)height, sizeof *line);
        if (!pf)
            rc = err_set(&err, "%s: cannot write", profile);
        else if (!line)
            rc = err_set(&err, "out of memory for the profile");
        double call = 1e30;
        for (int k = 0; pf && rc == 0 && k < PROFILE_CALLS; k++) {
            double a = timer_now();
            rc = render_span(pool, scene, width, height, 0, 1, pixels, NULL, NULL, &err);
            call = fmin(call, timer_now() - a);
        }
        for (int k = 0; pf && rc == 0 && k < PROFILE_PASSES; k++)
            for (int y = 0; rc == 0 && y < height; y++) {
                double a = timer_now();
                rc = render_lines(pool, scene, width, height, y, 1, pixels + (size_t)y * width * 3, NULL, &err);
                double t = timer_now() - a;
                line[y] = k == 0 ? t : fmin(line[y], t);
            }
        for (int y = 0; pf && rc == 0 && y < height; y++)
            fprintf(pf, "%d,%.1f\n", y, fmax(line[y] - call, 0.0) * 1e6);
        free(line);
        if (pf && fclose(pf) != 0 && rc == 0)
            rc = err_set(&err, "%s: write failed", profile);
    }
    if (rc == 0)
        rc = image_write(out, width, height, pixels, &err);
    if (rc)
        fprintf(stderr, "lanray-render: %s\n", err.msg);
    else {
        double rays = (double)(st.primary + st.shadow);
        printf("%dx%d aa %d%s %s shadows %s bvh %s threads %d (%s): frame %.4f s (mean %.4f s over %d), "
               "%.2f Mrays/s (%llu camera + %llu shadow rays)\n",
               width, height, rs->aa, rs->adaptive ? " adaptive" : "", rs->shading == SHADE_PHONG ? "phong" : "diffuse",
               rs->shadows ? "on" : "off", bvh_kind_name(bvh.kind), threads, REAL_NAME, best, sum / frames, frames,
               rays / best * 1e-6, (unsigned long long)st.primary, (unsigned long long)st.shadow);
        if (!quiet)
            printf("wrote %s\n", out);
    }
    free(pixels);
    render_pool_destroy(pool);
    scene_destroy(scene);
    return rc ? 1 : 0;
}

/* cli.c - see cli.h. */
#include "app/cli.h"
#include "base/simd.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "model/model_load.h"
#include "scene/scene_default.h"
#include "scene/scene_parse.h"
#include "scene/scene_preview.h"


static int parse_n(const char *s, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || *end || v < 1 || v > AA_MAX)
        return -1;
    *out = (int)v;
    return 0;
}

int cli_parse_simd(const char *v, void *dst, Err *err)
{
    (void)dst;
    char msg[160];
    if (simd_select(v, msg, sizeof msg))
        return err_set(err, "%s", msg);
    return 0;
}

int cli_simd_env(Err *err)
{
    const char *env = getenv("LANRAY_SIMD");
    char msg[160];
    if (env && simd_select(env, msg, sizeof msg))
        return err_set(err, "LANRAY_SIMD: %s", msg);
    return 0;
}

int cli_parse_aa(const char *v, void *dst, Err *err)
{
    (void)err;
    CliAa *a = dst, r = {4, 1, 1};
    if (strncmp(v, "adaptive", 8) == 0) {
        if (v[8] == ':' ? parse_n(v + 9, &r.aa) : v[8] != 0)
            return -1;
    } else {
        r.adaptive = 0;
        if (parse_n(v, &r.aa))
            return -1;
    }
    *a = r;
    return 0;
}

int cli_parse_segment(const char *v, void *dst, Err *err)
{
    (void)err;
    if (strcmp(v, "auto") == 0) {
        *(uint32_t *)dst = 0;
        return 0;
    }
    char *end;
    long n = strtol(v, &end, 10);
    if (end == v || *end || n < 1 || n > CLI_MAX_SEGMENT)
        return -1;
    *(uint32_t *)dst = (uint32_t)n;
    return 0;
}

int cli_threads(int requested)
{
    if (requested > 0)
        return requested;
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

int cli_open_scene(const char *path, const BvhOptions *bvh, int force, int smooth, Scene **out, Err *err)
{
    if (path && model_load_knows(path))
        return scene_preview(path, bvh, force, smooth, out, err);
    if (smooth) {
        *out = NULL;
        return err_set(err, "--smooth is for a model given alone; in a scene file, `model NAME FILE smooth`%s%s",
                       path ? ": " : " (the built-in scene's models have their normals)", path ? path : "");
    }
    if (!path)
        return scene_default(out, bvh, err);
    return scene_load(path, bvh, force, out, err);
}

void cli_warning(void *ctx, const char *msg)
{
    CliWarnings *w = ctx;
    if (w->shown < CLI_WARNINGS_SHOWN)
        fprintf(stderr, "%s: warning: %s\n", w->prog, msg);
    else if (w->shown == CLI_WARNINGS_SHOWN)
        fprintf(stderr, "%s: %s\n", w->prog, w->rest);
    w->shown++;
}

static CliWarnings load_warnings;

void cli_show_warnings(const char *prog)
{
    load_warnings = (CliWarnings){prog, "further warnings not shown (obj2tmd MODEL counts them all)", 0};
    model_load_warnings(cli_warning, &load_warnings);
}

void cli_put_light_paths(RenderSettings *rs, const CliLightPaths *l)
{
    if (l->clamp_given)
        rs->clamp_indirect = (real)l->clamp;
    if (l->blur_given)
        rs->filter_glossy = (real)l->blur;
    if (l->caustics_given)
        rs->caustics = (Caustics)l->caustics;
}

int cli_put_camera(Scene *s, const char *text, Err *err)
{
    Camera c;
    if (!text)
        return 0;
    if (scene_parse_camera(text, "--camera", &c, err))
        return -1;
    s->camera = c;
    return 0;
}

int cli_put_environment(Scene *s, const CliEnvironment *e, const char *path, Err *err)
{
    if (e->file) {
        Texture *t;
        uint32_t id;
        if (scene_add_source(s, e->file, err) || texture_read(e->file, &t, err) || scene_add_texture(s, t, &id, err))
            return err_prefix(err, "--environment");
        s->environment = (SceneEnvironment){.texture = (int32_t)id, .strength = R(1), .rotate = R(0)};
        if (path && model_load_knows(path)) { /* a model's preview: the environment its light from everywhere */
            if (s->preview_lamps) /* in place of the preview's own lamps (a glTF's own lights stay) */
                s->light_count = 0;
            s->ambient = v3_splat(R(0));
        }
    }
    if ((e->strength_given || e->rotate_given) && s->environment.texture < 0)
        return err_set(err, "--environment-strength and --environment-rotate change an environment, and the scene has "
                            "none: give --environment FILE");
    if (e->strength_given)
        s->environment.strength = (real)e->strength;
    if (e->rotate_given)
        s->environment.rotate = (real)e->rotate;
    s->checked = 0;
    return 0;
}

void cli_warn_scene(const char *prog, const Scene *s)
{
    /* (a path-traced scene is lit by its emitters and its background as
     * well; an environment lights both integrators' scenes) */
    if (s->light_count == 0 && s->settings.integrator != INTEGRATOR_PATH && s->environment.texture < 0)
        fprintf(stderr, "%s: warning: the scene has no light; only its ambient light (%g %g %g) shows it\n", prog,
                (double)s->ambient.x, (double)s->ambient.y, (double)s->ambient.z);
}

int cli_make_dirs(const char *dir, Err *err)
{
    char p[4096];
    if (snprintf(p, sizeof p, "%s", dir) >= (int)sizeof p)
        return err_set(err, "%s: directory name too long", dir);
    for (char *s = p + 1;; s++) {
        if (*s != '/' && *s != 0)
            continue;
        char c = *s;
        *s = 0;
        struct stat st;
        if (mkdir(p, 0777) != 0 && errno != EEXIST)
            return err_set(err, "cannot create directory %s: %s", p, strerror(errno));
        if (stat(p, &st) != 0 || !S_ISDIR(st.st_mode))
            return err_set(err, "%s is not a directory", p);
        *s = c;
        if (!c)
            return 0;
    }
}

uint64_t cli_available_memory(void)
{
    unsigned long long kb = 0;
    FILE *f = fopen("/proc/meminfo", "r");
    if (f) {
        char line[256];
        while (fgets(line, sizeof line, f))
            if (sscanf(line, "MemAvailable: %llu kB", &kb) == 1)
                break;
        fclose(f);
    }
    uint64_t have = (uint64_t)kb * 1024;
    /* a limit on the address space (ulimit -v) is as binding as the RAM */
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY && (have == 0 || (uint64_t)rl.rlim_cur < have))
        have = (uint64_t)rl.rlim_cur;
    return have;
}

/* "201 MB", "12.9 GB" */
static void bytes_text(uint64_t b, char *buf, size_t size)
{
    if (b < (uint64_t)10 << 30)
        snprintf(buf, size, "%.0f MB", (double)b / 1e6);
    else
        snprintf(buf, size, "%.1f GB", (double)b / 1e9);
}

int cli_check_memory(uint64_t bytes, const char *what, Err *err)
{
    uint64_t have = cli_available_memory();
    if (have && bytes > have) {
        char need[32], got[32];
        bytes_text(bytes, need, sizeof need);
        bytes_text(have, got, sizeof got);
        return err_set(err, "%s needs %s of memory; this machine has %s available", what, need, got);
    }
    return 0;
}

/* panel.c - see panel.h. */
#include "panel.h"

#include <stdio.h>

#include "upscale.h"

static const double targets[] = {0, 5, 10, 15, 24, 30, 60};
#define NTARGETS (int)(sizeof targets / sizeof *targets)

double panel_next_target(double target, int up)
{
    int i = 0;
    while (i + 1 < NTARGETS && targets[i + 1] <= target + 1e-9)
        i++;
    if (up)
        return targets[i + 1 < NTARGETS ? i + 1 : i];
    if (targets[i] < target - 1e-9) /* between two steps: down to the one below */
        return targets[i];
    return targets[i > 0 ? i - 1 : 0];
}

void panel_next_still(int path, int *refine, int *aa, int *adaptive)
{
    if (!*refine)
        *refine = 1, *aa = 2, *adaptive = 0;
    else if (*aa == 2 && !*adaptive)
        *aa = 4, *adaptive = 1;
    else if (*adaptive)
        *aa = 4, *adaptive = 0;
    else if (path && *aa < 16)
        *aa = 16;
    else if (path && *aa < 32)
        *aa = 32;
    else
        *refine = 0;
}

static void sampling_text(char *out, size_t size, int aa, int adaptive)
{
    if (adaptive && aa > 1)
        snprintf(out, size, "adaptive %dx%d", aa, aa);
    else
        snprintf(out, size, "%dx%d", aa, aa);
}

void panel_rate(char out[PANEL_RATE], int converged, double fps)
{
    if (converged)
        snprintf(out, PANEL_RATE, "converged");
    else
        snprintf(out, PANEL_RATE, "%.1f fps", fps);
}

int panel_lines(const PanelInfo *p, char out[][PANEL_LINE])
{
    int n = 0;
#define LINE(...) snprintf(out[n++], PANEL_LINE, __VA_ARGS__)
    char rate[PANEL_RATE];
    panel_rate(rate, p->converged, p->fps);
    /* frame_s is from a frame's start to its showing: a moving frame's
     * latency, longer than 1 / fps where the farm pipelines (18 fps and
     * "73 ms a frame" read as a contradiction) */
    if (p->still && p->samples > 1)
        LINE("%s  %.1f ms  still, %d samples a pixel", rate, p->frame_s * 1e3, p->samples); /* fits 400 pixels */
    else if (p->still)
        LINE("%s  %.1f ms a frame  still", rate, p->frame_s * 1e3);
    else
        LINE("%s  latency %.1f ms  moving", rate, p->frame_s * 1e3);
    const char *up = p->upscale_blocks ? "blocks" : "smooth";
    /* quarter steps: 1/2, 1/2.5, 1/2.75 */
    char scale[16];
    snprintf(scale, sizeof scale, "1/%g", p->scale / (double)UPSCALE_ONE);
    if (p->target_fps > 0)
        LINE("target %.0f fps [T/Shift+T]  render scale %s %s [U]", p->target_fps, scale, up);
    else
        LINE("target none [T]  render scale %s %s [U]", scale, up);
    char moving[32], still[32];
    sampling_text(moving, sizeof moving, p->aa, p->adaptive);
    if (p->refine)
        sampling_text(still, sizeof still, p->still_aa, p->still_adaptive);
    else
        snprintf(still, sizeof still, "off");
    if (p->refine && p->still_lights) {
        char lights[32];
        snprintf(lights, sizeof lights, "%dx%d", p->still_lights, p->still_lights);
        LINE("samples: moving %.16s, still %.16s, lights to %.9s [N]", moving, still, lights);
    } else
        LINE("samples: moving %s, still %s [N]", moving, still);
    char points[16] = "";
    if (p->moving_lights)
        snprintf(points, sizeof points, " %dx%d", p->moving_lights, p->moving_lights);
    LINE("moving lights %s%s [L]  %s [M]  shadows %s [H]", p->light_adaptive ? "adaptive" : "full", points,
         p->diffuse ? "diffuse" : "phong", p->shadows ? "on" : "off");
    if (p->denoise) /* a line of its own: the one above, longer, was cut by a window 400 pixels wide */
        LINE("frames shown %s [X]%s", p->denoise == 1 ? "denoised" : "raw",
             p->denoise == 1 && p->temporal ? ", moving ones added up" : "");
    else if (p->temporal) /* a Whitted view's history (--whitted-temporal) */
        LINE("moving frames near the full size added up (%d)", p->temporal);
    LINE("frames %dx%d, segments of %u lines", p->width, p->height, p->segment_lines);
    LINE("%u client%s", p->nclients, p->nclients == 1 ? "" : "s");
    double rest_share = 0, rest_rate = 0;
    for (uint32_t i = 0; i < p->nclients; i++) {
        const ServerClientInfo *c = &p->clients[i];
        if (i < PANEL_MAX_CLIENTS)
            LINE(" #%d %-21.21s %2u thr %6.0f lines/s %5.1f%%", c->id, c->addr, c->threads, c->lines_per_s,
                 100 * c->share);
        else
            rest_share += c->share, rest_rate += c->lines_per_s;
    }
    if (p->nclients > PANEL_MAX_CLIENTS)
        LINE(" %u more %6.0f lines/s %5.1f%%", p->nclients - PANEL_MAX_CLIENTS, rest_rate, 100 * rest_share);
    if (p->error)
        LINE("error: %.90s", p->error);
    LINE("WASD RF move, Shift fast, V mouse look");
    LINE("drag look, right drag orbit (Shift: pan), K print view");
    LINE("C frame all, Home reset, +/- zoom, Tab panel");
#undef LINE
    return n;
}

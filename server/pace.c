/* pace.c - see pace.h. */
#include "pace.h"

#include "upscale.h"

/* quarter steps (upscale.h): 1, 1.5, 2, 2.25, 2.5, 2.75, 3, 3.25, 3.5, 4,
 * 4.5, 5, 6, 8; from one to the next the pixels shrink by 1.2 to 2.3
 * times (the whole scales alone: 1.8 to 4, which left a 2-core farm at 22
 * fps where 10 was asked, the next finer scale out of reach; the half
 * steps 1.3 to 1.8: the demo's flight at 19-20 fps where 15 was asked) */
const int pace_scales[] = {4, 6, 8, 9, 10, 11, 12, 13, 14, 16, 18, 20, 24, 32};
const int pace_scale_count = (int)(sizeof pace_scales / sizeof pace_scales[0]);
_Static_assert(sizeof pace_scales / sizeof pace_scales[0] == PACE_SCALES, "a time for every scale");

/* With a target, the first moving frame is the coarsest (its cost is not
 * known yet: a fast first picture, refined as the times come in). */
void pace_init(Pace *p, double fps)
{
    *p = (Pace){.target = fps > 0 ? 1.0 / fps : 0, .scale = fps > 0 ? pace_scales[pace_scale_count - 1] : UPSCALE_ONE};
}

void pace_set_target(Pace *p, double fps)
{
    p->target = fps > 0 ? 1.0 / fps : 0;
    if (!(fps > 0))
        p->scale = UPSCALE_ONE;
}

/* The pixels rendered at scale index i: each side divided, rounded up. */
static double pixels_at(int i, uint32_t width, uint32_t height)
{
    const uint32_t s = (uint32_t)pace_scales[i];
    return (double)upscale_side(width, s) * (double)upscale_side(height, s);
}

/* Time t of a frame at scale index at, in proportion to the pixels at
 * scale index j (an overestimate where fixed costs weigh). */
static double proportional(double t, int j, int at, uint32_t width, uint32_t height)
{
    return t * pixels_at(j, width, height) / pixels_at(at, width, height);
}

/* The time predicted at scale index j: as measured there, else on the line
 * a + b x pixels through the two measured scales nearest j in pixels (a
 * frame's fixed cost and its cost a pixel, neither below 0), else in
 * proportion to the one measured. */
static double predict(const Pace *p, int j, uint32_t w, uint32_t h)
{
    if (p->t[j] > 0)
        return p->t[j];
    int a = -1, b = -1;
    for (int d = 1; d < pace_scale_count && b < 0; d++)
        for (int s = -1; s <= 1; s += 2) {
            const int i = j + s * d;
            if (i < 0 || i >= pace_scale_count || !(p->t[i] > 0) || b >= 0)
                continue;
            if (a < 0)
                a = i;
            else
                b = i;
        }
    if (a < 0)
        return 0;
    const double pa = pixels_at(a, w, h), pj = pixels_at(j, w, h);
    if (b < 0)
        return proportional(p->t[a], j, a, w, h);
    const double pb = pixels_at(b, w, h);
    double slope = (p->t[b] - p->t[a]) / (pb - pa);
    slope = slope > 0 ? slope : 0;
    double fixed = p->t[a] - slope * pa;
    fixed = fixed > 0 ? fixed : 0;
    return fixed + slope * pj;
}

int pace_update(Pace *p, double seconds, int scale, uint32_t width, uint32_t height)
{
    if (!(p->target > 0) || !(seconds > 0))
        return p->scale;
    int i = 0;
    while (i < pace_scale_count - 1 && pace_scales[i] != scale)
        i++;
    /* this scale's time, the last frames weighing most; the other scales'
     * follow it (the view turned to a costlier or a cheaper part) */
    const double old = p->t[i], now = old > 0 ? 0.5 * old + 0.5 * seconds : seconds;
    for (int j = 0; j < pace_scale_count && old > 0; j++)
        if (j != i)
            p->t[j] *= now / old;
    p->t[i] = now;
    if (now > p->target) { /* coarser at once, as far as it takes */
        while (i < pace_scale_count - 1 && predict(p, i, width, height) > p->target)
            i++;
        if (scale != p->scale && pace_scales[i] < p->scale)
            return p->scale; /* in flight is coarser still (see below) */
    } else if (scale != p->scale) {
        /* a frame started before the last change of scale (a pipelined
         * farm starts the next frame before this one is shown): its time
         * counts, but the scale in flight stays until a frame rendered at
         * it says how it fared.  Deciding from this frame as well made two
         * chains of decisions a frame apart that alternated, the picture's
         * sharpness flickering (4 and 4.5, 3.5 and 4.5 a frame each in the
         * demo's flight) */
        return p->scale;
    } else if (i > 0 && !(p->t[i - 1] > 0) && now <= PACE_PROBE * p->target) {
        /* far below the target and the finer scale never tried: try it, or
         * a finer one never tried whose time in proportion to its pixels
         * fits with room to spare (an overestimate where a small frame's
         * time is mostly fixed costs): the first move comes down from the
         * coarsest in a few frames, not one scale a frame */
        const int at = i;
        i--;
        while (i > 0 && !(p->t[i - 1] > 0) &&
               proportional(now, i - 1, at, width, height) <= PACE_FINER * p->target)
            i--;
    } else { /* finer only with room to spare */
        /* a scale never measured only where this frame's time in
         * proportion to its pixels (an overestimate) stays within
         * PACE_REACH of the target: times that disagree (more pixels
         * measured faster, a few frames' noise) make a line of slope 0
         * that predicts every finer scale at one time, and a flight went
         * from scale 4 to 1 for a frame of 410 ms */
        const int at = i;
        while (i > 0 && predict(p, i - 1, width, height) <= PACE_FINER * p->target &&
               (p->t[i - 1] > 0 ||
                proportional(now, i - 1, at, width, height) <= PACE_REACH * p->target))
            i--;
        /* the finer scale's time forgotten after PACE_RETRY such frames:
         * the next one tries it (the branch above) */
        p->easy = i == at && i > 0 && now <= PACE_FINER * p->target ? p->easy + 1 : 0;
        if (p->easy >= PACE_RETRY)
            p->t[i - 1] = 0, p->easy = 0;
    }
    if (pace_scales[i] != scale)
        p->easy = 0;
    p->scale = pace_scales[i];
    return p->scale;
}

/* A period of moving frames starts at `now`. */
static void period_start(Pace *p, double now)
{
    p->shown_t = now;
    p->shown_frames = 0;
    p->after_still = 0;
}

int pace_shown(Pace *p, double now, double started, int scale, uint32_t width, uint32_t height)
{
    if (p->after_still && started > p->shown_t)
        p->shown_t = started;
    p->after_still = 0;
    if (!(p->shown_t > 0) || !(p->target > 0)) { /* the first frame shown, or no target: a period starts */
        period_start(p, now);
        /* the first frame's time is its own, from its start (no frame
         * before it shares the farm): the first move comes down a frame
         * or two sooner (make demo without a display wrote its 9 moving
         * frames all at scales 8 to 3.25, the pace still coming down).
         * It moves the scale but is not kept: it may hold the scene's
         * upload to the clients (a 1M-triangle model's 0.5 s, which kept
         * the scale at 8 for a dozen frames while that time wore off) */
        if (!(started > 0 && started < now) || !(p->target > 0))
            return p->scale;
        const int next = pace_update(p, now - started, scale, width, height);
        for (int i = 0; i < pace_scale_count; i++)
            p->t[i] = 0;
        return next;
    }
    p->shown_frames++;
    const double since = now - p->shown_t;
    if (since < 0.5 * p->target)
        return p->scale;
    const int n = p->shown_frames;
    period_start(p, now);
    return pace_update(p, since / n, scale, width, height);
}

void pace_still(Pace *p, double now)
{
    period_start(p, now);
    p->after_still = 1;
}

/* pace.c - see pace.h. */
#include "pace.h"

const int pace_scales[] = {1, 2, 3, 4, 6, 8};
const int pace_scale_count = (int)(sizeof pace_scales / sizeof pace_scales[0]);

/* With a target, the first moving frame is the coarsest (its cost is not
 * known yet: a fast first picture, refined as the times come in). */
void pace_init(Pace *p, double fps)
{
    *p = (Pace){.target = fps > 0 ? 1.0 / fps : 0, .per_pixel = 0, .scale = fps > 0 ? pace_scales[pace_scale_count - 1] : 1};
}

/* The pixels rendered at a scale: each side divided, rounded up. */
static double pixels_at(int scale, uint32_t width, uint32_t height)
{
    const uint32_t k = (uint32_t)scale;
    return (double)((width + k - 1) / k) * (double)((height + k - 1) / k);
}

int pace_update(Pace *p, double seconds, int scale, uint32_t width, uint32_t height)
{
    if (!(p->target > 0) || !(seconds > 0))
        return p->scale;
    const double measured = seconds / pixels_at(scale, width, height);
    /* the last frames weigh most: a view that turns to a costly part shows at once */
    p->per_pixel = p->per_pixel > 0 ? 0.5 * p->per_pixel + 0.5 * measured : measured;
    int i = 0;
    while (i < pace_scale_count - 1 && pace_scales[i] != p->scale)
        i++;
    const double now = p->per_pixel * pixels_at(pace_scales[i], width, height);
    if (now > p->target) { /* coarser at once, as far as it takes */
        while (i < pace_scale_count - 1 && p->per_pixel * pixels_at(pace_scales[i], width, height) > p->target)
            i++;
    } else { /* finer only with room to spare */
        while (i > 0 && p->per_pixel * pixels_at(pace_scales[i - 1], width, height) <= PACE_FINER * p->target)
            i--;
    }
    p->scale = pace_scales[i];
    return p->scale;
}

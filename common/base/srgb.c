/* srgb.c - see srgb.h. */
#include "base/srgb.h"

#include <math.h>

double srgb_decode(double s)
{
    if (!(s > 0))
        return 0;
    if (s >= 1)
        return 1;
    return s <= 0.04045 ? s / 12.92 : pow((s + 0.055) / 1.055, 2.4);
}

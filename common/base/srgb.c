/* srgb.c - see srgb.h. */
#include "base/srgb.h"

#include "base/dmath.h"

#include <math.h>

double srgb_decode(double s)
{
    if (!(s > 0))
        return 0;
    if (s >= 1)
        return 1;
    return s <= 0.04045 ? s / 12.92 : dmath_pow((s + 0.055) / 1.055, 2.4);
}

void srgb_from_rgbe(const uint8_t *rgbe, size_t n, double gain, uint8_t *rgb)
{
    for (size_t i = 0; i < n; i++) {
        double c[3];
        rgbe_decode(rgbe + 4 * i, c);
        for (int k = 0; k < 3; k++)
            rgb[3 * i + k] = srgb_encode8((real)(c[k] * gain));
    }
}

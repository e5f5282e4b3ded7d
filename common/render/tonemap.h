/* tonemap.h - view transforms: how the light of a pixel, which may be far
 * past white (a lamp, the sun, their reflections), comes to 8-bit codes.
 * Without one (TONEMAP_NONE) each channel is cut at 1, so that a bright
 * surface goes flat white and a coloured light turns its hue as channels
 * clip one by one; a curve rolls it off instead, as a camera's film does
 * and as Blender's Filmic and AgX views do.  Two common ones:
 *
 * - ACES (TONEMAP_ACES): Krzysztof Narkowicz's fit of the ACES reference
 *   rendering transform, x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)
 *   per channel: contrast in the mid-tones, 1 reached only as x grows
 *   past 10, white at 1 shown 0.80.
 * - Khronos PBR Neutral (TONEMAP_NEUTRAL): colours kept as they are up to
 *   0.76 (less a small toe under 0.08), then the peak channel compressed
 *   towards 1 with the hue kept and a little desaturation: a glTF's base
 *   colours seen as they were authored.
 *
 * Applied where a pixel's codes are made (render/pixel.h), after the
 * exposure and before the sRGB (or linear) encoding; a .hdr keeps the light
 * itself.  Scalar arithmetic in a fixed order: the same bits on every path. */
#ifndef LANRAY_TONEMAP_H
#define LANRAY_TONEMAP_H

#include "base/vec.h"
#include "scene/scene.h"

static inline real tonemap_aces(real x)
{
    if (!(x > R(0)))
        return R(0);
    return x * (R(2.51) * x + R(0.03)) / (x * (R(2.43) * x + R(0.59)) + R(0.14));
}

static inline vec3 tonemap_neutral(vec3 c)
{
    const real start = R(0.76), desaturation = R(0.15);
    const real x = real_min(c.x, real_min(c.y, c.z));
    const real offset = x < R(0.08) ? x - R(6.25) * x * x : R(0.04);
    c = v3_sub(c, v3_splat(offset));
    const real peak = real_max(c.x, real_max(c.y, c.z));
    if (!(peak >= start)) /* also a NaN: as it is */
        return c;
    const real d = R(1) - start;
    const real top = R(1) - d * d / (peak + d - start);
    c = v3_scale(c, top / peak);
    const real g = R(1) - R(1) / (desaturation * (peak - top) + R(1));
    return v3_add(v3_scale(c, R(1) - g), v3_splat(top * g));
}

/* Light c through view transform t. */
static inline vec3 tonemap_apply(vec3 c, Tonemap t)
{
    if (t == TONEMAP_ACES)
        return v3(tonemap_aces(c.x), tonemap_aces(c.y), tonemap_aces(c.z));
    if (t == TONEMAP_NEUTRAL)
        return tonemap_neutral(c);
    return c;
}

#endif

/* dielectric.h - how a dielectric surface splits a ray, for both
 * integrators (shade.c, path.c): the share reflected by Fresnel's
 * equations (or Schlick's: settings fresnel), and where the rest goes;
 * what its inside absorbs; and the share a clear coat reflects. */
#ifndef LANRAY_DIELECTRIC_H
#define LANRAY_DIELECTRIC_H

#include "base/dmath.h"
#include "scene/trace.h"
#include "shading/ggx.h"
#include "shading/optics.h"

/* The ratio of indices a ray at dielectric surface sf crosses: the one
 * it leaves over the one it enters. */
static inline real dielectric_eta(const Surface *sf) { return sf->inside ? sf->mat->ior : R(1) / sf->mat->ior; }

/* What frosted glass at sf seen from unit `view` (on the side of sf->ns)
 * weighs its single-scattering lobe by, for the light its facets pass
 * between them (ggx_glass_weight): the same for every direction the
 * light leaves in, so made once a hit. */
static inline real dielectric_frost_weight(const Surface *sf, vec3 view)
{
    return ggx_glass_weight(v3_dot(sf->ns, view), sf->mat->roughness, dielectric_eta(sf));
}

/* The share of light along unit d reflected at dielectric surface sf by
 * its part of unit normal n (its shading normal, or a frosted surface's
 * facet), the ratio of indices *eta it crosses and the refracted
 * direction *td (not unit; zero where none): all of it reflected past the
 * critical angle, or where n would bend the refracted ray back through
 * the facet. */
static inline real dielectric_split_at(const World *w, const Surface *sf, vec3 n, vec3 d, real *eta, vec3 *td)
{
    *eta = dielectric_eta(sf);
    real f = optics_fresnel(w->view.settings.fresnel, real_max(R(0), -v3_dot(d, n)), *eta);
    *td = v3_splat(R(0));
    if (f >= R(1) || !optics_refract(d, n, *eta, td) || !(v3_dot(*td, sf->ng) < R(0)))
        f = R(1);
    return f;
}

/* dielectric_split_at the shading normal. */
static inline real dielectric_split(const World *w, const Surface *sf, vec3 d, real *eta, vec3 *td)
{
    return dielectric_split_at(w, sf, sf->ns, d, eta, td);
}

/* What light keeps of itself per channel crossing the inside of
 * dielectric material m to hit h: exp(-absorb x t) (Beer-Lambert), t in
 * the absorption's units (trace_absorb_t: a model's own glass by its
 * model's).  For both integrators and the Whitted shadow rays. */
static inline vec3 dielectric_absorbed(const World *w, const Material *m, const Hit *h)
{
    const real t = trace_absorb_t(w, h);
    return v3(dmath_expr(-m->absorb.x * t), dmath_expr(-m->absorb.y * t), dmath_expr(-m->absorb.z * t));
}

/* The share of the light a clear coat (material.h's `coat`) at surface sf
 * reflects towards unit direction `view` (to the viewer): coat x Fresnel's
 * reflectance of index MATERIAL_COAT_IOR at the angle to the shading
 * normal (settings fresnel's model).  The rest of the surface takes
 * 1 - this. */
static inline real dielectric_coat_share(const World *w, const Surface *sf, vec3 view)
{
    const real c = real_clamp(v3_dot(sf->ns, view), R(0), R(1));
    return sf->mat->coat * optics_fresnel(w->view.settings.fresnel, c, R(1) / MATERIAL_COAT_IOR);
}

#endif

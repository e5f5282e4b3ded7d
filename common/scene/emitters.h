/* emitters.h - emissive geometry as lights, for the path integrator.
 *
 * Every emissive sphere, scene triangle and model triangle that is not a
 * light's lamp (the light stands for it: scene.h) lights the scene by
 * next-event estimation: a diffuse point picks one of them in proportion
 * to its power (area x mean emitted radiance) and a point on it (a sphere
 * by the cone of directions it fills seen from outside, else uniformly by
 * area), and emitters_pdf gives the density of that choice for a direction
 * that a bounce found instead, so that the path integrator can weigh the
 * two by multiple importance sampling.  Planes, unbounded, are met by
 * paths only.  Emission is two-sided, as it is where a path meets it. */
#ifndef LANRAY_EMITTERS_H
#define LANRAY_EMITTERS_H

#include "scene/trace.h"

struct Emitter {
    HitKind kind;  /* HIT_SPHERE, HIT_TRIANGLE or HIT_INSTANCE */
    uint32_t index, sub; /* as in a Hit */
    real cdf;      /* the probability of picking this emitter or one before it */
    real share;    /* its emission texture's mean over it (emitters.c's glow_share), 1 without one */
    uint32_t cells; /* a textured triangle's cells in World.emit_cells (emitters.c's glow_cells):
                     * where its points are drawn by brightness; EMITTER_NO_CELLS: uniformly */
};

#define EMITTER_NO_CELLS UINT32_MAX

/* Builds w's table (w->emitters; none where nothing emits).  After the
 * lamps are paired. */
int emitters_build(World *w, Err *err);

/* A sampled point of an emitter seen from p. */
typedef struct {
    vec3 dir;      /* unit, from p */
    real dist;     /* to the point */
    vec3 radiance; /* what it emits towards p */
    real pdf;      /* density of dir (solid angle), the emitter's pick included */
} EmitterSample;

/* Picks an emitter by `pick` and a point of it by (u, v), all in [0, 1).
 * 0 where p sees no emitting side of it (on its plane, at its centre). */
int emitters_sample(const World *w, vec3 p, real pick, real u, real v, EmitterSample *out);

/* The density (solid angle) with which emitters_sample from p picks the
 * direction of ray r (unit direction), which met h at h->t: 0 for what it
 * never samples (a plane, a lamp, a surface that emits nothing). */
real emitters_pdf(const World *w, vec3 p, const Ray *r, const Hit *h);

#endif

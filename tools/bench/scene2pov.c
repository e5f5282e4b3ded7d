/* scene2pov - a lanray scene as a POV-Ray 3.7 scene, for make bench's
 * comparison at matched error (tools/bench/bench-pov).
 *
 *   scene2pov [SCENE] -o OUT.pov [--width W] [--height H] [--aa N]
 *
 * SCENE is a scene file, a model (a preview scene, as lanray-render's), or
 * the built-in default scene without one (cli_open_scene).  What
 * it writes, item by item:
 *   camera      the pinhole as explicit location, direction, right and up
 *               vectors (POV-Ray then shoots direction + x right + y up,
 *               lanray's camera_dir exactly); other camera kinds refused;
 *   lights      point lights; spots (POV-Ray's spotlight with the cone's
 *               inner and outer half-angles); directional lights
 *               (parallel); sphere lights as a circular area light
 *               oriented to each point (the disc lanray samples) and
 *               rectangles as an area light on their edges, each with its
 *               samples x samples, jittered; a light with attenuation is
 *               refused (POV-Ray's fade is 2 / (1 + d^2), not 1 / d^2);
 *               a light's lamp (its emissive primitives) casts no shadow;
 *   materials   pigment kd (or a checker of kd and kc, or the texture as
 *               an image map on the texture coordinates, written beside
 *               OUT.pov as texN.ppm), ambient (the scene's ambient),
 *               diffuse 1, Phong as `phong` (the mean of ks) with
 *               `phong_size` the shininess, mirrors as reflection kr
 *               (with reflect_edge a variable reflection from kr to it,
 *               falloff 5: Schlick's (1 - cos)^5),
 *               dielectrics as an interior of their index with Fresnel
 *               reflection, conserve_energy, a filter of kt and absorption
 *               as exponential fade, emission as `emission`, a clear coat
 *               as Fresnel reflection of its strength over an interior of
 *               index 1.5;
 *   geometry    spheres, planes, scene triangles and each model once as a
 *               mesh2 (normals and texture coordinates where it has them)
 *               placed by a matrix per instance.
 * Settings: the depth as max_trace_level, the cutoff as adc_bailout, the
 * background, and with --aa N > 1 POV-Ray's own anti-aliasing (+A0.0,
 * method 1, depth N) in the file's comment for the caller to pass.
 * What POV-Ray has no match for is refused or told (an environment is
 * refused): a rough mirror,
 * frosted glass or rough clear coat is written as a plain one (a
 * warning), a coat over a mirror left out (a warning), a model's own
 * materials as its first. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/cli.h"
#include "base/fileio.h"
#include "base/opt.h"
#include "geom/camera.h"
#include "scene/world.h"

typedef struct {
    const char *scene_path, *out;
    int width, height;
} Args;

static void vec(FILE *f, vec3 v) { fprintf(f, "<%.9g, %.9g, %.9g>", (double)v.x, (double)v.y, (double)v.z); }

static void rgb(FILE *f, vec3 c) { fprintf(f, "rgb <%.9g, %.9g, %.9g>", (double)c.x, (double)c.y, (double)c.z); }

/* texN.ppm beside out: texture t's image as lanray holds it, top row
 * first (POV-Ray's uv_mapping then reads it as lanray does: checked by
 * the default scene's picture, which a flipped file turns upside down). */
static int write_texture(const char *out, uint32_t n, const Texture *t, Err *err)
{
    char path[4096];
    const char *slash = strrchr(out, '/');
    int dirlen = slash ? (int)(slash - out + 1) : 0;
    snprintf(path, sizeof path, "%.*stex%u.ppm", dirlen, out, n);
    size_t row = 3u * t->w, len = row * t->h;
    char head[64];
    int hl = snprintf(head, sizeof head, "P6\n%u %u\n255\n", t->w, t->h);
    uint8_t *buf = malloc((size_t)hl + len);
    if (!buf)
        return err_set(err, "out of memory");
    memcpy(buf, head, (size_t)hl);
    memcpy(buf + hl, t->level[0].rgb, len);
    int rc = file_write_bytes(path, buf, (size_t)hl + len, err);
    free(buf);
    return rc;
}

/* Material m's surface as a POV-Ray texture { pigment finish }. */
static void write_surface(FILE *f, const World *w, const Material *m)
{
    const int black_emitter = material_emits(m) && !(v3_max_comp(m->kd) > R(0)) && m->texture < 0;
    fprintf(f, "  texture {\n    ");
    if (material_dielectric(m)) {
        fprintf(f, "pigment { color rgbf <%.9g, %.9g, %.9g, 1> }\n", (double)m->kt.x, (double)m->kt.y, (double)m->kt.z);
    } else if (m->texture >= 0) {
        const Texture *t = w->textures[m->texture];
        fprintf(f, "pigment { uv_mapping image_map { ppm \"tex%d.ppm\" gamma srgb%s } }\n", m->texture,
                t->closest ? "" : " interpolate 2");
    } else if (material_checkered(m)) {
        fprintf(f, "pigment { %schecker color ", m->checker_uv ? "uv_mapping " : "");
        rgb(f, m->kd);
        fprintf(f, " color ");
        rgb(f, m->kc);
        fprintf(f, " scale %.9g }\n", (double)m->checker_size);
    } else {
        /* POV-Ray's emission is times the pigment: a black emitter a white pigment that no light reaches */
        fprintf(f, "pigment { color ");
        rgb(f, black_emitter ? v3_splat(1) : m->kd);
        fprintf(f, " }\n");
    }
    const real phong = (m->ks.x + m->ks.y + m->ks.z) / R(3);
    fprintf(f, "    finish { ambient ");
    rgb(f, material_dielectric(m) ? v3_splat(0) : w->ambient);
    fprintf(f, " diffuse %s specular 0", material_dielectric(m) || black_emitter ? "0" : "1");
    if (phong > R(0) && w->view.settings.shading == SHADE_PHONG)
        fprintf(f, " phong %.9g phong_size %.9g", (double)phong, (double)m->shininess);
    if (material_dielectric(m))
        fprintf(f, " reflection { 0, 1 fresnel on } conserve_energy");
    else if (material_reflects(m)) {
        fprintf(f, " reflection { ");
        rgb(f, m->kr);
        if (material_edged(m)) { /* rising to kre as (1 - cos)^5: POV-Ray's variable reflection is that form */
            fprintf(f, ", ");
            rgb(f, m->kre);
            fprintf(f, " falloff 5");
        }
        fprintf(f, " }");
    } else if (material_coats(m)) /* Fresnel's share of the interior's index (1.5), the rest to the surface */
        fprintf(f, " reflection { 0, %.9g fresnel on } conserve_energy", (double)m->coat);
    if (material_emits(m)) { /* ke over the pigment's colour, channel by channel */
        vec3 e = m->ke;
        for (int k = 0; k < 3 && !black_emitter; k++)
            e.e[k] = m->kd.e[k] > R(0) ? m->ke.e[k] / m->kd.e[k] : R(0);
        fprintf(f, " emission ");
        rgb(f, e);
    }
    fprintf(f, " }\n  }\n");
}

/* #declare name: material m as a POV-Ray material (its surface and a glass's interior). */
static void write_material(FILE *f, const World *w, const Material *m, const char *name)
{
    fprintf(f, "#declare %s = material {\n", name);
    write_surface(f, w, m);
    if (material_coats(m) && !material_reflects(m))
        fprintf(f, "  interior { ior %.9g }\n", (double)MATERIAL_COAT_IOR);
    if (material_dielectric(m)) {
        fprintf(f, "  interior { ior %.9g", (double)m->ior);
        if (v3_max_comp(m->absorb) > R(0))
            fprintf(f, " fade_distance 1 fade_power 1001 fade_color rgb <%.9g, %.9g, %.9g>", exp(-(double)m->absorb.x),
                    exp(-(double)m->absorb.y), exp(-(double)m->absorb.z));
        fprintf(f, " }\n");
    }
    fprintf(f, "}\n");
}

/* The camera and the lights; -1 after saying why where POV-Ray has no match. */
static int write_view(FILE *f, const World *w, int width, int height, Err *err)
{
    const Camera *c = &w->view.camera;
    if (c->kind != CAMERA_PINHOLE || c->aperture > R(0))
        return err_set(err, "only the pinhole camera without a lens is written");
    if (w->env) /* a sky_sphere is only seen: it lights a scene through radiosity alone */
        return err_set(err, "an environment is not written (POV-Ray's sky_sphere lights nothing without radiosity)");
    CameraFrame cf = camera_frame(c, width, height);
    /* camera_dir(x, y) = u x + v y + k over x in [0, W], y in [0, H] down
     * the image: direction its centre, right u W, up -v H, made
     * perpendicular again in double (POV-Ray warns at float's rounding) */
    vec3 centre = camera_dir(&cf, R(0.5) * (real)width, R(0.5) * (real)height);
    double d[3], r[3], u[3];
    for (int k = 0; k < 3; k++)
        d[k] = (double)centre.e[k], r[k] = (double)cf.u.e[k] * width, u[k] = -(double)cf.v.e[k] * height;
    double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], rd = (r[0] * d[0] + r[1] * d[1] + r[2] * d[2]) / dd;
    for (int k = 0; k < 3; k++)
        r[k] -= rd * d[k];
    double rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    double ud = (u[0] * d[0] + u[1] * d[1] + u[2] * d[2]) / dd, ur = (u[0] * r[0] + u[1] * r[1] + u[2] * r[2]) / rr;
    for (int k = 0; k < 3; k++)
        u[k] -= ud * d[k] + ur * r[k];
    fprintf(f, "camera {\n  perspective\n  location ");
    vec(f, cf.org);
    fprintf(f, "\n  direction <%.17g, %.17g, %.17g>\n  right <%.17g, %.17g, %.17g>\n  up <%.17g, %.17g, %.17g>\n}\n", d[0],
            d[1], d[2], r[0], r[1], r[2], u[0], u[1], u[2]);
    for (uint32_t i = 0; i < w->light_count; i++) {
        const WorldLight *l = &w->lights[i];
        if (l->attenuate)
            return err_set(err, "light %u is attenuated (POV-Ray fades by 2 / (1 + d^2))", i + 1);
        vec3 at = l->kind == LIGHT_RECT ? v3_add(l->pos, v3_scale(v3_add(l->edge1, l->edge2), R(0.5))) : l->pos;
        fprintf(f, "light_source { ");
        vec(f, l->kind == LIGHT_DIRECTIONAL ? v3_scale(l->axis, R(-1e6)) : at);
        fprintf(f, " color ");
        rgb(f, v3_scale(l->color, l->intensity));
        if (l->kind == LIGHT_SPOT) {
            fprintf(f, " spotlight point_at ");
            vec(f, v3_add(l->pos, l->axis));
            fprintf(f, " radius %.9g falloff %.9g tightness 0", acos((double)l->cos_inner) * 180 / 3.14159265358979,
                    acos((double)l->cos_outer) * 180 / 3.14159265358979);
        } else if (l->kind == LIGHT_DIRECTIONAL) {
            fprintf(f, " parallel point_at <0, 0, 0>");
        } else if (l->kind == LIGHT_SPHERE) {
            fprintf(f, " area_light <%.9g, 0, 0>, <0, 0, %.9g>, %d, %d jitter circular orient", 2 * (double)l->radius,
                    2 * (double)l->radius, l->samples, l->samples);
        } else if (l->kind == LIGHT_RECT) {
            fprintf(f, " area_light ");
            vec(f, l->edge1);
            fprintf(f, ", ");
            vec(f, l->edge2);
            fprintf(f, ", %d, %d jitter", l->samples, l->samples);
        }
        fprintf(f, " }\n");
    }
    return 0;
}

/* Whether top-level primitive p is any light's lamp. */
static int is_lamp(const World *w, uint32_t p)
{
    for (uint32_t k = 0; k < w->lamp_total; k++)
        if (w->lamps[k] == p)
            return 1;
    return 0;
}

/* A model as #declare MODEL_i = mesh2 { ... } (no texture: the instance's),
 * and with `own` (a model of several materials) MODEL_i_OWN with each
 * face's material as a texture of its list (their interiors are not
 * written: one object has one). */
static void write_model(FILE *f, const World *w, const Model *m, uint32_t i, int own)
{
    fprintf(f, "#declare MODEL_%u%s = mesh2 {\n  vertex_vectors { %u", i, own ? "_OWN" : "", 3 * m->tri_count);
    for (uint32_t t = 0; t < m->tri_count; t++)
        for (int c = 0; c < 3; c++) {
            fprintf(f, ",\n    ");
            vec(f, tri_vertex(&m->tris[t], c));
        }
    fprintf(f, " }\n");
    if (m->normals) {
        fprintf(f, "  normal_vectors { %u", 3 * m->tri_count);
        for (uint32_t k = 0; k < 3 * m->tri_count; k++) {
            fprintf(f, ",\n    ");
            vec(f, m->normals[k]);
        }
        fprintf(f, " }\n");
    }
    if (m->uvs) {
        fprintf(f, "  uv_vectors { %u", 3 * m->tri_count);
        for (uint32_t k = 0; k < 3 * m->tri_count; k++)
            fprintf(f, ",\n    <%.9g, %.9g>", (double)m->uvs[2 * k], (double)m->uvs[2 * k + 1]);
        fprintf(f, " }\n");
    }
    if (own) {
        fprintf(f, "  texture_list { %u,\n", m->material_count);
        for (uint32_t k = 0; k < m->material_count; k++)
            write_surface(f, w, &m->materials[k]);
        fprintf(f, "  }\n");
    }
    fprintf(f, "  face_indices { %u", m->tri_count);
    for (uint32_t t = 0; t < m->tri_count; t++) {
        fprintf(f, ",\n    <%u, %u, %u>", 3 * t, 3 * t + 1, 3 * t + 2);
        if (own)
            fprintf(f, ", %u", m->mat_ids[t]);
    }
    fprintf(f, " }\n}\n");
}

/* Spheres, planes, scene triangles and instances. */
static void write_items(FILE *f, const World *w)
{
    for (uint32_t i = 0; i < w->sphere_count; i++) {
        const Sphere *sp = &w->spheres[i];
        fprintf(f, "sphere { ");
        vec(f, sp->centre);
        fprintf(f, ", %.9g material { M_%u }%s }\n", (double)sp->radius, sp->material, is_lamp(w, i) ? " no_shadow" : "");
    }
    for (uint32_t i = 0; i < w->plane_count; i++) {
        const WorldPlane *p = &w->planes[i];
        fprintf(f, "plane { ");
        vec(f, p->unit);
        fprintf(f, ", %.9g material { M_%u } }\n", (double)v3_dot(p->point, p->unit), p->material);
    }
    for (uint32_t i = 0; i < w->tri_count; i++) {
        const TriAttr *a = &w->tri_attrs[i];
        fprintf(f, "mesh2 { vertex_vectors { 3");
        for (int c = 0; c < 3; c++) {
            fprintf(f, ", ");
            vec(f, tri_vertex(&w->tris[i], c));
        }
        fprintf(f, " }");
        if (a->textured)
            fprintf(f, " uv_vectors { 3, <%.9g, %.9g>, <%.9g, %.9g>, <%.9g, %.9g> }", (double)a->uv[0], (double)a->uv[1],
                    (double)a->uv[2], (double)a->uv[3], (double)a->uv[4], (double)a->uv[5]);
        fprintf(f, " face_indices { 1, <0, 1, 2> } material { M_%u }%s }\n", a->material,
                is_lamp(w, w->sphere_count + i) ? " no_shadow" : "");
    }
    for (uint32_t i = 0; i < w->desc->model_count; i++) {
        write_model(f, w, w->models[i], i, 0);
        if (w->models[i]->mat_ids && w->models[i]->material_count)
            write_model(f, w, w->models[i], i, 1);
    }
    for (uint32_t i = 0; i < w->instance_count; i++) {
        const WorldInstance *in = &w->instances[i];
        const Model *m = w->models[in->model];
        /* x' = s R x + t, as POV-Ray's row-vector matrix: rows are R's columns */
        if (in->material >= 0)
            fprintf(f, "object { MODEL_%u material { M_%d } matrix <", in->model, in->material);
        else if (m->mat_ids && m->material_count)
            fprintf(f, "object { MODEL_%u_OWN matrix <", in->model);
        else
            fprintf(f, "object { MODEL_%u material { M_0 } matrix <", in->model);
        for (int c = 0; c < 3; c++)
            fprintf(f, "%.9g, %.9g, %.9g, ", (double)(in->rot.r[0].e[c] * in->scale),
                    (double)(in->rot.r[1].e[c] * in->scale), (double)(in->rot.r[2].e[c] * in->scale));
        fprintf(f, "%.9g, %.9g, %.9g> }\n", (double)in->translate.x, (double)in->translate.y, (double)in->translate.z);
    }
}

typedef struct {
    const World *w;
    const Args *a;
} PovJob;

/* The .pov file (file_write_atomic's writer). */
static int write_pov(FILE *f, void *ctx, Err *err)
{
    const PovJob *job = ctx;
    const World *w = job->w;
    const Args *a = job->a;
    const RenderSettings *st = &w->view.settings;
    fprintf(f, "// written by lanray's scene2pov: %s\n#version 3.7;\n", a->scene_path ? a->scene_path : "the default scene");
    fprintf(f, "global_settings { assumed_gamma 1.0 ambient_light rgb 1 max_trace_level %d adc_bailout %.9g }\n",
            st->depth + 1, (double)st->cutoff);
    fprintf(f, "background { color ");
    rgb(f, w->background);
    fprintf(f, " }\n");
    int rc = write_view(f, w, a->width, a->height, err);
    for (uint32_t i = 0; rc == 0 && i < w->material_count; i++) {
        char name[32];
        snprintf(name, sizeof name, "M_%u", i);
        write_material(f, w, &w->materials[i], name);
        if (material_rough(&w->materials[i]))
            fprintf(stderr, "scene2pov: warning: material %u is a rough mirror, written as a smooth one\n", i + 1);
        if (material_frosted(&w->materials[i]))
            fprintf(stderr, "scene2pov: warning: material %u is frosted glass, written as clear glass\n", i + 1);
        if (material_coats(&w->materials[i]) && material_reflects(&w->materials[i]))
            fprintf(stderr, "scene2pov: warning: material %u: a clear coat over a mirror, left out\n", i + 1);
        else if (material_coats(&w->materials[i]) && !material_coat_smooth(&w->materials[i]))
            fprintf(stderr, "scene2pov: warning: material %u: a rough clear coat, written as a smooth one\n", i + 1);
    }
    for (uint32_t i = 0; rc == 0 && i < w->desc->texture_count; i++)
        rc = write_texture(a->out, i, w->textures[i], err);
    if (rc == 0)
        write_items(f, w);
    return rc;
}

static int parse_args(Args *a, int argc, char **argv)
{
    *a = (Args){.width = 1024, .height = 768};
    const Opt opts[] = {
        {.name = "--output", .alias = "-o", .kind = OPT_STRING, .dst = &a->out, .arg = "FILE", .help = "the .pov file"},
        {.name = "--width", .kind = OPT_INT, .dst = &a->width, .arg = "W", .lo = 1, .hi = 65536, .help = "frame width"},
        {.name = "--height", .kind = OPT_INT, .dst = &a->height, .arg = "H", .lo = 1, .hi = 65536, .help = "frame height"},
        {0},
    };
    const char *args[1] = {NULL};
    OptSpec spec = {.prog = "scene2pov", .synopsis = "[SCENE] -o OUT.pov [options]",
                    .about = "Writes a lanray scene, a model's preview or the built-in default scene as a POV-Ray 3.7 scene.",
                    .opts = opts, .args = args, .min_args = 0, .max_args = 1, .missing = "",
                    .exits = "  0  written\n  1  an error, or what POV-Ray has no match for\n  2  bad command line\n"};
    int go = opt_run(&spec, argc, argv);
    a->scene_path = args[0];
    if (go == OPT_GO && !a->out) {
        fprintf(stderr, "scene2pov: needs -o OUT.pov\n");
        return 2;
    }
    return go;
}

int main(int argc, char **argv)
{
    Args a;
    int rc = parse_args(&a, argc, argv);
    if (rc != OPT_GO)
        return rc;
    Err err;
    Scene *s = NULL;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    if (cli_open_scene(a.scene_path, &opt, 0, 0, &s, &err)) {
        fprintf(stderr, "scene2pov: %s\n", err.msg);
        return 1;
    }
    World *w = world_build(s, NULL, &err);
    PovJob job = {w, &a};
    rc = !w || file_write_atomic(a.out, write_pov, &job, &err);
    if (rc)
        fprintf(stderr, "scene2pov: %s\n", err.msg);
    world_destroy(w);
    scene_destroy(s);
    return rc;
}

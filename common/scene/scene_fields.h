/* scene_fields.h - the scene's kinds of item as field tables (field.h):
 * camera, settings, light, sphere, plane, triangle, instance (the material's
 * is in shading/material.h).  The scene parser, the scene on the wire, the
 * scene's checks and docs/scene.md's tables all walk these.
 *
 * Where a directive says more than the item keeps (a camera's `lookat`, a
 * spot light's `target`, settings' `adaptive`), the table describes a spec:
 * the item first, then those keys; scene_fields_finish_* turns a spec into
 * the item.  A spec's item starts at offset 0, so the wire encodes items
 * through their specs. */
#ifndef LANRAY_SCENE_FIELDS_H
#define LANRAY_SCENE_FIELDS_H

#include "base/field.h"
#include "scene/scene.h"

typedef struct {
    Camera cam;
    vec3 lookat; /* file: turned into yaw and pitch */
    real fov;    /* file: a pinhole's field of view, turned into zoom */
} CameraSpec;

typedef struct {
    RenderSettings rs;
    int adaptive; /* file: `adaptive N` is aa N, adaptively */
} SettingsSpec;

typedef struct {
    Light l;
    vec3 target; /* file: a spot light's direction as the point it aims at */
} LightSpec;

/* A scene triangle as the file and the wire say it (the scene keeps it as
 * a Tri and a TriAttr). */
typedef struct {
    real vertices[9], normals[9], uv[6];
    int material;
    int smooth, textured; /* wire: the normals and uv hold */
} TriSpec;

/* A model directive's keys (the model itself is an asset, not on the wire as fields). */
typedef struct {
    int bvh, smooth;
} ModelSpec;

/* An instance as a scene file gives it: the Instance (first: its fields'
 * offsets are the wire's), and what it takes from its model's file. */
typedef struct {
    Instance in;
    int lights, camera;
} InstanceSpec;

extern const FieldKind model_kind;
extern const FieldKind environment_kind;
extern const FieldKind camera_kind, settings_kind, light_kind, sphere_kind, plane_kind, triangle_kind, instance_kind;

/* The directives whose tables docs/scene.md shows, in its order. */
extern const FieldKind *const scene_kinds[];

/* A camera from what its directive gave (the file's rules were checked
 * by field_read): the pinhole's zoom from fov or zoom, the angles from
 * lookat or yaw and pitch, the kind from ortho or fisheye.  -1 where the
 * lookat point is the position. */
int scene_fields_finish_camera(CameraSpec *sp, FieldSet given);
/* Settings from what their directive gave: aa or adaptive. */
void scene_fields_finish_settings(SettingsSpec *sp, FieldSet given);
/* A light from what its directive gave: a spot's target as a direction;
 * NULL, or what is wrong (a spot or directional light without a direction). */
const char *scene_fields_finish_light(LightSpec *sp, FieldSet given);

/* The camera as a scene file's `camera` line that reads back as the same
 * camera, field for field (position and angles, zoom or the projection's
 * width or field of view, the lens), into buf: its length, or how long
 * it would be (snprintf). */
int camera_line(const Camera *c, char *buf, size_t size);

/* What is wrong with a camera's, a light's values (the table's ranges and
 * what holds between fields), into buf; or NULL. */
const char *camera_problem(const Camera *c, char *buf, size_t size);
const char *light_problem(const Light *l, char *buf, size_t size);
const char *settings_problem(const RenderSettings *rs, char *buf, size_t size);

/* The triangle's spec from the scene's triangle i, and back. */
TriSpec tri_spec(const Scene *s, uint32_t i);
int scene_add_tri_spec(Scene *s, const TriSpec *t, Err *err);

#endif

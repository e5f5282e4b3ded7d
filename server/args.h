/* args.h - lanray-server's command line: its options (the table in
 * args.c, which --help prints and docs/tools.md copies), and the settings
 * it puts over every scene the server reads (the first, an edited one, a
 * file dropped on the window). */
#ifndef LANRAY_SERVER_ARGS_H
#define LANRAY_SERVER_ARGS_H

#include "app/cli.h"
#include "base/err.h"
#include "bvh/bvh.h"
#include "scene/scene.h"
#include "server.h"

/* What the command line says. */
typedef struct {
    ServerConfig cfg;
    BvhOptions bvh;
    const char *scene_path, *out_dir, *verify_path;
    int headless, force_bvh, discard, frames, wait_clients, tail, bvh_kind, width_given, height_given, smooth;
    int warmup, stall, handshake, machine_summary, linear, hdr;
    int denoise; /* --denoise, or the first scene's settings denoise: fixed for the server's life */
    int denoise_given;
    int fixed_size; /* --fixed-size: the window's frames keep their size */
    const char *camera; /* --camera, */
    Camera cam;         /* ... read once (open_scene) */
    int integrator, integrator_given, tonemap, tonemap_given;
    CliLightPaths paths;
    CliAa aa;
    double rotate;
    const char *path;
    double path_step;
    CliAa still;
    int still_lights;
    int moving_lights, moving_lights_given, moving_light_samples;
    int compress, announce, pipeline;
    double target_fps, max_fps, render_scale;
    int target_given;
    CliEnvironment env;
} Args;


/* Parses the command line into a: OPT_GO, or the exit status. */
int args_parse(Args *a, int argc, char **argv);
/* The command line's settings over a scene's own, the scene of `path`;
 * -1 with err set where its environment cannot be put. */
int args_apply(Scene *scene, const Args *a, const char *path, Err *err);
/* --smooth for the scene of `path`: a model's alone (a scene file's models say it themselves). */
int args_smooth_for(const Args *a, const char *path);

#endif

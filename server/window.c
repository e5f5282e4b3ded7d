/* window.c - see window.h. */
#include "window.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/timer.h"
#include "panel.h"
#include "scene/scene_fields.h"
#include "upscale.h"

void window_init(Window *w, Display *d, Server *s, Pace *pace, double target_fps, const Scene *scene, int width,
                 int height, int follow)
{
    *w = (Window){.display = d, .server = s, .pace = pace, .knobs = {-1, -1}, .target_fps = target_fps,
                  .width = width, .height = height, .follow = follow, .asked_w = width, .asked_h = height};
    window_new_scene(w, scene);
}

void window_new_scene(Window *w, const Scene *scene)
{
    w->home = scene->camera;
    vec3 centre = v3_splat(0);
    real radius = R(1);
    if (scene_bounds(scene, &centre, &radius))
        centre = v3_splat(0), radius = R(1);
    nav_init(&w->nav, centre, radius);
}

void window_knobs_apply(const Window *w, RenderSettings *rs)
{
    if (w->knobs.shading >= 0)
        rs->shading = (ShadeModel)w->knobs.shading;
    if (w->knobs.shadows >= 0)
        rs->shadows = w->knobs.shadows;
}

/* The still quality N steps to (panel_next_still: a path-traced view's
 * goes on to 16x16 and 32x32). */
static void next_still(Server *s)
{
    int refine, aa, adaptive;
    server_still(s, &refine, &aa, &adaptive);
    panel_next_still(server_settings(s).integrator == INTEGRATOR_PATH, &refine, &aa, &adaptive);
    server_set_still(s, refine, aa, adaptive);
}

/* The knobs' keys: settings for the next frame, kept for scenes to come. */
static void turn_knobs(Window *w, const DisplayInput *in)
{
    if (in->toggle_lights) { /* the moving frames': a still one is lanray-render's picture */
        server_set_moving_lights(w->server, server_moving_lights(w->server) == LIGHTS_FULL ? LIGHTS_ADAPTIVE : LIGHTS_FULL);
    }
    if (in->toggle_shading || in->toggle_shadows) {
        RenderSettings rs = server_settings(w->server);
        if (in->toggle_shading)
            w->knobs.shading = rs.shading = rs.shading == SHADE_PHONG ? SHADE_DIFFUSE : SHADE_PHONG;
        if (in->toggle_shadows)
            w->knobs.shadows = rs.shadows = !rs.shadows;
        server_set_settings(w->server, &rs);
    }
    if (in->toggle_denoise && server_denoises(w->server)) /* the raw frame beside the filtered one */
        server_set_denoise_shown(w->server, !server_denoise_shown(w->server));
    if (in->toggle_upscale)
        server_set_upscale(w->server, server_upscale(w->server) == UPSCALE_SMOOTH ? UPSCALE_BLOCKS : UPSCALE_SMOOTH);
    if (in->next_still)
        next_still(w->server);
    if (in->target_up || in->target_down) {
        w->target_fps = panel_next_target(w->target_fps, in->target_up);
        pace_set_target(w->pace, w->target_fps);
        server_set_scale(w->server, w->pace->scale);
    }
}

/* The frames at the window's size, as an image viewer would not but a
 * renderer's viewport does: a larger window gets more pixels, not the
 * same ones stretched (the server takes it between frames). */
static void follow_size(Window *w)
{
    int ow, oh;
    display_output_size(w->display, &ow, &oh);
    if (ow == w->asked_w && oh == w->asked_h)
        return;
    w->asked_w = ow, w->asked_h = oh;
    server_set_size(w->server, ow, oh);
}

int window_poll(Window *w, int *animate, int *screenshot)
{
    DisplayInput in;
    display_poll(w->display, &in);
    if (w->follow)
        follow_size(w);
    const double now = timer_now(), dt = w->last_poll > 0 ? now - w->last_poll : 0;
    w->last_poll = now;
    if (in.quit)
        return 1;
    Camera cam = server_camera(w->server), *c = &cam;
    int changed = 0;
    if (in.reset) {
        *c = w->home;
        w->nav.vel = v3_splat(0);
        changed = 1;
    }
    if (in.frame_all) {
        nav_frame_all(&w->nav, c, w->width, w->height);
        changed = 1;
    }
    changed |= nav_move(&w->nav, c, v3((real)in.right, (real)in.up, (real)in.forward), in.fast, dt);
    const double yaw = in.yaw + in.turn * NAV_TURN_DEG_S * dt;
    if (yaw || in.pitch) {
        c->yaw += (real)yaw;
        c->pitch = real_clamp(c->pitch + (real)in.pitch, -89, 89);
        changed = 1;
    }
    if (in.pan_x || in.pan_y) { /* the pointer's pixels on the frame as drawn */
        nav_pan(&w->nav, c, in.pan_x, in.pan_y, display_drawn_width(w->display));
        changed = 1;
    }
    if (in.orbit_yaw || in.orbit_pitch) {
        nav_orbit(&w->nav, c, (real)in.orbit_yaw, (real)in.orbit_pitch);
        changed = 1;
    }
    if (in.zoom) {
        c->zoom *= pow(R(1.1), (real)in.zoom);
        changed = 1;
    }
    if (changed)
        server_set_camera(w->server, c);
    if (in.print_view) { /* a view found in the window, for a scene file or lanray-render --camera */
        char line[512];
        camera_line(c, line, sizeof line);
        const int copied = display_clipboard(w->display, line) == 0;
        fprintf(stderr, "lanray-server: the view%s: %s\n", copied ? " (on the clipboard)" : "", line);
    }
    if (in.toggle_animation)
        *animate = !*animate;
    if (in.screenshot)
        *screenshot = 1;
    if (in.dropped[0])
        memcpy(w->dropped, in.dropped, sizeof w->dropped);
    turn_knobs(w, &in);
    if (in.toggle_panel) {
        w->panel_on = !w->panel_on;
        window_panel(w, w->fps, NULL);
    }
    return 0;
}

void window_panel(Window *w, double fps, const char *error)
{
    char lines[PANEL_MAX_LINES][PANEL_LINE];
    int n = 0;
    w->fps = fps;
    if (w->panel_on) {
        ServerClientInfo clients[PANEL_MAX_CLIENTS + 56];
        const RenderSettings rs = server_settings(w->server);
        PanelInfo p = {.fps = fps, .frame_s = server_last_frame_time(w->server), .target_fps = w->target_fps,
                       .scale = server_frame_scale(w->server),
                       .upscale_blocks = server_upscale(w->server) == UPSCALE_BLOCKS, .still = server_frame_still(w->server),
                       .converged = server_frame_converged(w->server),
                       .samples = server_frame_samples(w->server),
                       .aa = rs.aa, .adaptive = rs.adaptive,
                       .light_adaptive = server_moving_lights(w->server) == LIGHTS_ADAPTIVE,
                       .moving_lights = server_moving_light_samples(w->server),
                       .diffuse = rs.shading == SHADE_DIFFUSE, .shadows = rs.shadows,
                       .denoise = server_denoises(w->server) ? 2 - server_denoise_shown(w->server) : 0,
                       .temporal = server_temporal(w->server),
                       .segment_lines = server_segment_lines(w->server), .width = w->width, .height = w->height,
                       .clients = clients, .error = error};
        server_still(w->server, &p.refine, &p.still_aa, &p.still_adaptive);
        p.still_lights = server_still_lights(w->server);
        p.nclients = server_clients_info(w->server, clients, sizeof clients / sizeof *clients);
        n = panel_lines(&p, lines);
    }
    Err err;
    if (display_panel(w->display, lines, n, &err)) {
        fprintf(stderr, "lanray-server: %s\n", err.msg);
        w->panel_on = 0;
    }
}

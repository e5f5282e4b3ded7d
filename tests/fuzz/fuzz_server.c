/* fuzz_server.c - the server's packet parser: every byte one client sends.
 *
 * Each input is a client's whole stream to a fresh server (a small scene
 * without assets, a 16x8 frame, 2-line segments, no token) through one end
 * of a socketpair.  When the first byte is odd the harness sends a valid
 * HELLO first and steps the server until frame 1 has started (its segments
 * are 0+32 and 32+32), so that the rest lands in an active session (DATA,
 * BYE, ERROR and whatever else); otherwise the rest is the stream from its
 * first byte (the handshake itself), 256 bytes a step.  When its bit 2 is set the scene is
 * path-traced and denoised, refined at --still-aa 2: frames after the
 * first are batches of samples, whose DATA carries sums the server adds
 * up (render/progressive.h), and the frames go through the history
 * (--temporal 8, render/temporal.h) before the denoiser; otherwise frame
 * 1, a moving one, carries its pixels' guides to the Whitted history
 * (--whitted-temporal 2).  The server steps until it has read
 * everything and closed the connection; what it sends back is dropped. */
#include <fcntl.h>
#include <stdio.h>
#include <sys/socket.h>
#include <unistd.h>

#include "fuzz.h"
#include "base/real.h"
#include "net/msg.h"
#include "net/pixcodec.h"
#include "scene/scene_parse.h"
#include "server.h"

static Scene *scene, *path_scene;

static Scene *parse_scene(const char *settings)
{
    /* no models or textures: a server serialises its assets when it is created */
    char text[512];
    const int n = snprintf(text, sizeof text,
                           "camera position 0 1 4 lookat 0 0.5 0 fov 50\n%s"
                           "material red diffuse 0.8 0.2 0.1 specular 0.5 0.5 0.5 shininess 30\n"
                           "plane point 0 0 0 normal 0 1 0 material red\n"
                           "sphere centre 0 0.5 0 radius 0.5 material red\n"
                           "light point position 2 4 3 intensity 1\n",
                           settings);
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Scene *s;
    if (scene_parse(text, (size_t)n, "fuzz.scene", ".", &opt, 0, &s, NULL) || scene_check(s, NULL))
        abort();
    return s;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!scene) {
        scene = parse_scene("");
        path_scene = parse_scene("settings integrator path denoise on\n");
    }
    if (size < 1 || size > 1 << 20)
        return 0;
    ServerConfig cfg = {0};
    cfg.width = 16;
    cfg.height = 8;
    cfg.segment_lines = 2;
    cfg.tail = sched_tail_static;
    cfg.stall_timeout = 60;
    cfg.handshake_timeout = 60;
    cfg.quiet = 1;
    cfg.moving_lights = -1;
    cfg.coding = PIX_ZSTD | PIX_PREDICT; /* the default: coded DATA decoded, as the seeds send it */
    cfg.whitted_temporal = 2;            /* the default: a Whitted frame 1 (moving) carries guides to the history */
    cfg.denoise_threads = 1;             /* ... whose stage runs on one thread (none started a run for more) */
    const int batches = data[0] & 2;
    if (batches)
        cfg.refine = 1, cfg.still_aa = 2, cfg.temporal = 8;
    Err err;
    Server *s = server_create(&cfg, batches ? path_scene : scene, &err);
    int fds[2];
    if (!s || socketpair(AF_UNIX, SOCK_STREAM, 0, fds))
        abort();
    fcntl(fds[0], F_SETFL, O_NONBLOCK);
    fcntl(fds[1], F_SETFL, O_NONBLOCK);
    server_adopt(s, fds[0], "fuzz");
    uint8_t sink[65536];
    if (data[0] & 1) {
        /* by the encoder: its layout is the protocol's, whatever its version */
        MsgOut o;
        msg_encode_hello(&(MsgHello){.magic = PROTO_MAGIC, .version = PROTO_VERSION, .bom = PROTO_BOM, .threads = 1,
                                     .real_size = (uint32_t)sizeof(real), .codecs = PIX_CODEC_MASK},
                         &o);
        fuzz_send_msg(fds[1], &o);
        /* the server welcomes the client and starts frame 1: its UPDATE goes out */
        for (int k = 0; k < 4; k++) {
            if (server_step(s, 0, NULL, NULL, &err))
                abort();
            while (read(fds[1], sink, sizeof sink) > 0) {
            }
        }
    }
    size_t off = 1;
    for (int round = 0; round < 100000; round++) {
        if (off < size) {
            /* a little a step, as a network brings it: a frame's results
             * arrive after it started, and the next frame starts between */
            const size_t chunk = size - off < 256 ? size - off : 256;
            ssize_t w = send(fds[1], data + off, chunk, MSG_NOSIGNAL);
            if (w > 0)
                off += (size_t)w;
            if (off == size)
                shutdown(fds[1], SHUT_WR);
        } else if (size == 1 && round == 0) {
            shutdown(fds[1], SHUT_WR);
        }
        if (server_step(s, 0, NULL, NULL, &err))
            break;
        ssize_t r;
        while ((r = read(fds[1], sink, sizeof sink)) > 0) {
        }
        if (r == 0)
            break; /* the server closed the connection */
    }
    close(fds[1]);
    server_destroy(s);
    return 0;
}

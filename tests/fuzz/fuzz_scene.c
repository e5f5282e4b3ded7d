/* fuzz_scene.c - the scene-file parser on arbitrary bytes; file references
 * point into a directory that does not exist, so they fail cleanly.  The
 * same bytes as a --camera's text (scene_parse_camera: one line, a camera
 * directive or its fields) first, which leaves them as they were. */
#include "fuzz.h"
#include "scene/scene_parse.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    if (!text)
        return 0;
    Camera c;
    Err err;
    scene_parse_camera(text, "--camera", &c, &err);
    Scene *s;
    BvhOptions opt = bvh_options_default(BVH_SAH);
    if (scene_parse(text, size, "fuzz.scene", "/nonexistent-lanray-fuzz", &opt, 0, &s, NULL) == 0)
        scene_destroy(s);
    free(text);
    return 0;
}

/* fuzz_path.c - the camera-path parser (--path) on arbitrary bytes; an
 * accepted path is flown: every camera it gives, at its keys, between them
 * and beyond its ends, must pass the camera checks, since the server sends
 * them to clients as they are. */
#include <assert.h>

#include "fuzz.h"
#include "scene/camera_path.h"
#include "scene/scene_fields.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    if (!text)
        return 0;
    CameraPath p;
    if (camera_path_parse(text, size, "fuzz.path", &p, NULL) == 0) {
        const real end = camera_path_end(&p);
        for (int i = -1; i <= 16; i++) {
            Camera c = camera_path_at(&p, end * (real)i / R(15));
            char why[160];
            assert(!camera_problem(&c, why, sizeof why));
        }
        camera_path_free(&p);
    }
    free(text);
    return 0;
}

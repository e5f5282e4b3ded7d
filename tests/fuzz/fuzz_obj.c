/* fuzz_obj.c - the OBJ reader on arbitrary bytes (no mtllib: no directory),
 * decoded from UTF-16 first when the bytes start with its byte-order mark,
 * as obj_read does. */
#include "fuzz.h"
#include "model/obj.h"
#include "base/textenc.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    if (!text)
        return 0;
    size_t len = size;
    Err err;
    if (text_to_utf8(&text, &len, "fuzz.obj", &err)) {
        free(text);
        return 0;
    }
    Mesh m;
    ObjOptions opt = {.smooth = size > 0 && (data[0] & 1), .strict = size > 0 && (data[0] & 2)};
    if (obj_parse(text, len, "fuzz.obj", NULL, &opt, &m, NULL, NULL) == 0)
        mesh_free(&m);
    free(text);
    return 0;
}

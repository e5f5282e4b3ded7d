/* fuzz_obj.c - the OBJ reader on arbitrary bytes (no mtllib: no directory). */
#include "fuzz.h"
#include "obj.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    if (!text)
        return 0;
    Mesh m;
    ObjOptions opt = {size > 0 && (data[0] & 1)};
    if (obj_parse(text, size, "fuzz.obj", NULL, &opt, &m, NULL, NULL) == 0)
        mesh_free(&m);
    free(text);
    return 0;
}

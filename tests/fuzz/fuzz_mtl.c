/* fuzz_mtl.c - the MTL reader on arbitrary bytes, decoded from UTF-16
 * first when they start with its byte-order mark, as mtl_read does. */
#include "fuzz.h"
#include "model/mtl.h"
#include "base/textenc.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    if (!text)
        return 0;
    size_t len = size;
    Err err;
    if (text_to_utf8(&text, &len, "fuzz.mtl", &err)) {
        free(text);
        return 0;
    }
    MtlLib lib = {0};
    mtl_parse(&lib, text, len, "fuzz.mtl", NULL);
    if (lib.count)
        mtl_find(&lib, lib.names[0]);
    mtl_free(&lib);
    free(text);
    return 0;
}

/* fuzz_mtl.c - the MTL reader on arbitrary bytes. */
#include "fuzz.h"
#include "mtl.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    if (!text)
        return 0;
    MtlLib lib = {0};
    mtl_parse(&lib, text, size, "fuzz.mtl", NULL);
    if (lib.count)
        mtl_find(&lib, lib.names[0]);
    mtl_free(&lib);
    free(text);
    return 0;
}

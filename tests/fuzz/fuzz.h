/* fuzz.h - the libFuzzer entry point every harness defines.  Built with
 * clang -fsanitize=fuzzer for `make fuzz`, or with replay.c's main for
 * `make check`, which runs the corpus and every saved crash input. */
#ifndef LANRAY_FUZZ_H
#define LANRAY_FUZZ_H

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#endif

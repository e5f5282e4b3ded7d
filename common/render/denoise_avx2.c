/* denoise_avx2.c - the denoiser's weighing passes (denoise_kernel.h)
 * compiled for AVX2 (base/avx2_begin.h: eight lanes a register, never
 * FMA); denoise.c calls them only where the CPU has it, and they give the
 * baseline's bits. */
#include "render/denoise.h"

#include "base/avx2_begin.h"
#define DENOISE_KERNEL(name) name##_avx2
#include "render/denoise_kernel.h"
#include "base/avx2_end.h"

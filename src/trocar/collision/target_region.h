#pragma once
/// TROCAR_TARGET_REGION_BEGIN("avx2,fma") … TROCAR_TARGET_REGION_END(): every function defined
/// between the two is compiled for that instruction-set target, whatever the library's baseline
/// (the kernels are chosen at run time, cpu_features.h). GCC takes the target for a region by
/// `#pragma GCC target`; clang ignores that pragma and takes an attribute applied to every
/// function defined in the region instead, so each compiler gets its own form. Open the region
/// after the library headers, so that only the kernel code is compiled for the target.
#define TROCAR_PRAGMA(text) _Pragma(#text)
#if defined(__clang__)
#define TROCAR_TARGET_REGION_BEGIN(isa) \
  TROCAR_PRAGMA(clang attribute push(__attribute__((target(isa))), apply_to = function))
#define TROCAR_TARGET_REGION_END() TROCAR_PRAGMA(clang attribute pop)
#else
#define TROCAR_TARGET_REGION_BEGIN(isa) TROCAR_PRAGMA(GCC push_options) TROCAR_PRAGMA(GCC target(isa))
#define TROCAR_TARGET_REGION_END() TROCAR_PRAGMA(GCC pop_options)
#endif

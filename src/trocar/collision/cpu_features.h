#pragma once
/// Internal to the collision module: which vector paths this CPU can take, checked once at run
/// time (the build targets baseline x86-64; the AVX2 functions are compiled per function with a
/// target attribute). TROCAR_SIMD=off in the environment forces the portable paths, as in the
/// tissue module.

namespace trocar::collision_cpu {

/// The CPU has AVX2 (and TROCAR_SIMD is not "off").
bool avx2();
/// The CPU has AVX2 and FMA (and TROCAR_SIMD is not "off").
bool avx2_fma();

}  // namespace trocar::collision_cpu

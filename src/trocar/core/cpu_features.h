#pragma once
/// Which vector paths this CPU can take, checked once at run time. The build targets baseline
/// x86-64; the AVX2 functions of the tissue, geometry and collision modules are compiled per
/// function with a target attribute and called only where these say so. TROCAR_SIMD=off in the
/// environment forces the portable paths everywhere (to compare, or to rule the vector code out).

namespace trocar {

/// The CPU has AVX2, and TROCAR_SIMD is not "off".
bool cpu_has_avx2();
/// The CPU has AVX2 and FMA, and TROCAR_SIMD is not "off".
bool cpu_has_avx2_fma();
/// The CPU has AVX-512 F, VL and DQ (512-bit vectors, mask registers, compress) besides AVX2 and
/// FMA, and TROCAR_SIMD is not "off".
bool cpu_has_avx512();

}  // namespace trocar

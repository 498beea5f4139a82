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

/// The widest kernels this process takes, by the three checks above. The floating-point results
/// (and so a simulation's state hash) can differ between paths: FMA contracts a·b + c with one
/// rounding, and the vector loops sum in another order.
enum class KernelPath { kPortable, kAvx2NoFma, kAvx2, kAvx512 };

/// This process's kernel path.
KernelPath kernel_path();
/// "portable", "avx2-nofma", "avx2" or "avx512" (what a session recording stores).
const char* kernel_path_name(KernelPath path);

/// Caps the kernel path for the rest of the process (a path the CPU lacks is never taken:
/// the cap only narrows). For tests that compare paths in one process; objects built before
/// the call keep the path they chose. Not thread-safe against running simulations.
void cap_kernel_path(KernelPath widest);

}  // namespace trocar

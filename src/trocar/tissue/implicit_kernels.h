#pragma once
/// The implicit (backward Euler + conjugate gradients) step in AVX2+FMA over padded vectors:
/// the same linear system, preconditioner, warm start and stopping rule as
/// integrator_implicit.cpp (which stays the portable reference), laid out for 256-bit vectors.
/// Used when the CPU has AVX2+FMA and the area term is off (the area term's implicit part is
/// only in the portable solver). Internal to the tissue module.
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/tissue/explicit_kernels.h"
#include "trocar/tissue/forces.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"
#include "trocar/tissue/volume_fans.h"

namespace trocar {
struct ImplicitOptions;
struct StepStats;
}  // namespace trocar

namespace trocar::tissue_detail {

/// Four springs' share of the system matrix for one step: block −(a u uᵀ + b I) between i and
/// j (integrator_implicit.cpp), kept as a u uᵀ = (a/|d|²) d dᵀ with d = x_j − x_i recomputed
/// from the step's positions in each product: 96 bytes per quad instead of 224 with u stored,
/// so a CG iteration on a mesh whose cache does not fit in L2 streams less than half the bytes.
struct alignas(32) CgSpringQuad {
  std::uint32_t i[4] = {};  ///< first vertex × sizeof(Padded3)
  std::uint32_t j[4] = {};  ///< second vertex × sizeof(Padded3)
  Real a_d[4] = {};         ///< a/|d|², a = h (λ + h k (1 − c)) (N·s/m³); 0 when degenerate
  Real b[4] = {};           ///< h² k c (N·s/m)
};

/// A symmetric 3×3 block as two padded rows: diagonal (xx, yy, zz, 0), off-diagonal (xy, yz, zx, 0).
struct alignas(32) Block3 {
  Real diagonal[4] = {};
  Real off[4] = {};
};

/// Scratch of the AVX2 implicit step, sized once; step() does not allocate.
class ImplicitAvx2 {
 public:
  explicit ImplicitAvx2(const MassSpringSettings& settings);
  /// Copies the home anchors again (after yield_home() moved them).
  void home_moved(const MassSpringSettings& settings);

  /// True when this solver handles `terms` (the area term is off or zero).
  static bool supports(const MassSpringSettings& s, const ForceTerms& terms);

  /// One backward Euler step of `state` (fixed vertices: velocities already zero; the caller
  /// restores their positions). Returns CG iterations, residual and finiteness.
  StepStats step(MassSpringState& state, const TissueLoads& loads, Real h, const ForceTerms& terms,
                 const ImplicitOptions& options);

 private:
  void linearise(const TissueLoads& loads, Real h, const ForceTerms& terms);
  Real apply_system(const TissueLoads& loads, Real h, Real volume_slope, const ForceTerms& terms);

  const MassSpringSettings& settings_;
  SpringLayout springs_;                       ///< the springs' parameters, four by four
  VolumeLayout triangles_;                     ///< the triangles in fans (the volume term)
  std::vector<CgSpringQuad> cache_stars_, cache_others_;  ///< this step's spring blocks
  PaddedArrays arrays_;  ///< storage of the spans below, staggered against 4K aliasing
  std::span<Padded3> x_, v_, rest_, f_, dv_, r_, p_, z_, q_, gradient_;
  std::vector<Block3> preconditioner_;         ///< A_ii, then inverted in place
  std::vector<Real> diagonal_mass_, free_;
  Real six_volume_ = 0;
};

}  // namespace trocar::tissue_detail

#pragma once
/// Time integration of a mass-spring tissue.
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/tissue/explicit_kernels.h"
#include "trocar/tissue/explicit_sweep.h"
#include "trocar/tissue/implicit_kernels.h"
#include "trocar/tissue/forces.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"
#include "trocar/tissue/xpbd.h"

namespace trocar {

/// The integrators a scene can choose per tissue (scene key `integrator`, docs/scene.md "Tissues").
enum class IntegratorKind {
  kExplicitEuler,      ///< x += h v; v += h a(x, v)           (the seed's)
  kSemiImplicitEuler,  ///< v += h a(x, v); x += h v          (symplectic)
  kImplicitEuler,      ///< backward Euler, one Newton step, CG (Baraff & Witkin 1998)
  kXpbd,               ///< XPBD with substeps, contact inside the solver (xpbd.h)
};

/// "explicit-euler", "semi-implicit-euler", "implicit-euler", "xpbd".
const char* integrator_name(IntegratorKind kind);
/// Parses the names above; throws trocar::Error listing the valid names.
IntegratorKind integrator_from_name(std::string_view name);

/// Options of the implicit solve.
struct ImplicitOptions {
  int max_cg_iterations = 100;   ///< conjugate-gradient iteration cap
  /// CG stops at a relative residual |r|/|b| ≤ cg_tolerance, or when the block-Jacobi estimate
  /// of the remaining velocity error, max_i |A_ii⁻¹ r_i|, is ≤ cg_tolerance × 0.1 m/s (1e-5 m/s
  /// at the default; docs/tissue-integrators.md gives the error this leaves).
  Real cg_tolerance = 1e-4;
};

/// What one step did (for metrics and tests).
struct StepStats {
  int cg_iterations = 0;         ///< implicit only
  Real cg_residual = 0;          ///< implicit only: final relative residual
  bool finite = true;            ///< false when a position or velocity became non-finite
  int substeps = 0;              ///< xpbd only: substeps (one constraint pass each)
  /// Relative constraint error left by the step: implicit, the CG's relative residual; xpbd,
  /// the largest spring strain |l − l0|/l0 in the last pass.
  Real constraint_error = 0;
};

/// Steps one tissue. Holds scratch buffers sized at construction, so step() never allocates.
class MassSpringIntegrator {
 public:
  MassSpringIntegrator(const MassSpringSettings& settings, IntegratorKind kind, ImplicitOptions options = {},
                       XpbdOptions xpbd = {});

  /// Advances `state` by dt seconds under the internal forces and `loads` (external forces,
  /// and for the implicit integrator also the contacts' Jacobians). Fixed vertices keep
  /// their position bit for bit and zero velocity.
  StepStats step(MassSpringState& state, const TissueLoads& loads, Real dt);

  IntegratorKind kind() const { return kind_; }
  /// The implicit solve's options (what the constructor took).
  const ImplicitOptions& implicit_options() const { return options_; }
  /// xpbd: the contact handler every step solves inside its substeps (null: none). Not owned.
  void set_contacts(XpbdContacts* contacts) { contacts_ = contacts; }
  XpbdContacts* contacts() const { return contacts_; }
  /// The settings' home anchors moved (yield_home()): copies them again where a pass keeps its own.
  void home_moved();
  /// The settings' springs `springs` changed stiffness, rest length or damping (coagulation):
  /// copies them again in place where it can (xpbd; no allocation) and returns true; false where
  /// it cannot (the other kinds keep them in layouts built once: rebuild the integrator).
  bool springs_changed(std::span<const std::uint32_t> springs);
  /// xpbd: the solver (null for the other kinds).
  XpbdSolver* xpbd() { return xpbd_.get(); }
  const XpbdSolver* xpbd() const { return xpbd_.get(); }
  const MassSpringSettings& settings() const { return settings_; }
  ForceTerms& terms() { return terms_; }  ///< which force terms are on (all by default)
  const ForceTerms& terms() const { return terms_; }
  /// Whether the AVX2+FMA passes run (default: when the CPU has them). Off forces the portable
  /// scalar passes, e.g. to compare the two; on is ignored where the CPU lacks AVX2/FMA.
  /// (Turning it off builds the pass-by-pass arrays if they were not: not during a step.)
  void set_simd(bool on);
  bool simd() const { return use_avx2_; }
  /// Explicit integrators with AVX2 on: whether the step runs as one sweep over blocks of vertices
  /// (explicit_sweep.h) rather than pass by pass. Default: where the passes' arrays exceed the L2
  /// cache (tissue_detail::sweep_pays). Setting it builds the sweep's layout if needed (it
  /// allocates: not during a step). The two agree to rounding; the area term always runs pass
  /// by pass.
  void set_explicit_sweep(bool on);
  bool explicit_sweep() const { return use_avx2_ && sweep_on_ && sweep_ != nullptr; }

 private:
  StepStats step_explicit(MassSpringState& state, const TissueLoads& loads, Real dt, bool symplectic);
  StepStats step_implicit(MassSpringState& state, const TissueLoads& loads, Real dt);
  /// Allocates the pass-by-pass explicit step's arrays and layouts (once; explicit kinds only).
  void build_passes();
  /// Restores the fixed vertices' positions bit for bit and zeroes their velocities.
  void end_step(MassSpringState& state) const;
  /// One spring's share of the system matrix A for the current step (see
  /// integrator_implicit.cpp): with δ = p_j − p_i, g = a (u·δ) u + b δ is subtracted from (A p)_i
  /// and added to (A p)_j (a, b in N·s/m, see integrator_implicit.cpp).
  struct CachedSpring {
    Real u[3];  ///< unit direction x_j − x_i (0 when degenerate)
    Real a;     ///< h (λ + h k (1 − c))
    Real b;     ///< h² k c
    std::uint32_t i, j;
  };
  /// One triangle's Gauss–Newton area stiffness in A: g_c = h √κ ∂A/∂x_c per corner, so the
  /// triangle adds (Σ_c g_c·p_c) g_c to (A p) at each corner c.
  struct CachedTriangle {
    Real g[3][3];
    std::uint32_t v[3];
  };
  /// A symmetric 3×3 block (xx, yy, zz, xy, xz, yz).
  struct Sym3 {
    Real m[6];
  };
  /// Builds the spring and triangle caches, ∇V, the block-Jacobi preconditioner's diagonal
  /// blocks (not yet inverted) and b = h (f₀ + h K v₀) (into residual_), for this step.
  void linearise(const MassSpringState& state, const TissueLoads& loads, Real h);
  /// product_ = A·p (direction_) on the free vertices (unfiltered at fixed ones, where p = 0);
  /// returns pᵀ A p, accumulated term by term during the passes. `volume_slope` = ∇V·p.
  Real apply_system(const TissueLoads& loads, Real h, Real volume_slope);

  const MassSpringSettings& settings_;
  IntegratorKind kind_;
  std::unique_ptr<XpbdSolver> xpbd_;   ///< xpbd only
  XpbdContacts* contacts_ = nullptr;   ///< xpbd only
  ImplicitOptions options_;
  ForceTerms terms_;
  // Scratch of the portable implicit solve, sized V at construction for the implicit kind:
  // forces_ is f₀ (+ h K v₀), dv_ is Δv (kept between steps: the next solve starts from it),
  // residual_ the CG residual r, direction_ the direction p, product_ A·p, scratch_ the
  // preconditioned z.
  std::vector<Vec3> forces_, dv_, residual_, direction_, product_, scratch_;
  // Explicit: spring and area forces, and Σ n_t per vertex, padded for the AVX2 passes; both
  // are all zero between steps (the update pass zeroes what it reads).
  tissue_detail::PaddedArrays padded_;  ///< storage of the five spans below
  std::span<tissue_detail::Padded3> pair_forces_, padded_volume_gradient_;
  std::span<tissue_detail::Padded3> padded_positions_, padded_velocities_;  ///< copies of the state
  std::span<tissue_detail::Padded3> padded_rest_;  ///< the rest positions
  tissue_detail::SpringLayout spring_layout_;  ///< the springs, four by four
  tissue_detail::VolumeLayout volume_layout_;  ///< the triangles in fans (volume term)
  /// Explicit: the passes fused into one sweep (explicit_sweep.h), built where the CPU has
  /// AVX2+FMA and the sweep is on; used unless the area term is on.
  std::unique_ptr<tissue_detail::ExplicitSweep> sweep_;
  bool sweep_on_ = false;
  bool passes_built_ = false;  ///< build_passes() ran
  /// Implicit: the AVX2 solver (where the CPU has AVX2+FMA), used unless the area term is on.
  std::unique_ptr<tissue_detail::ImplicitAvx2> implicit_avx2_;
  bool use_avx2_ = false;  ///< the CPU has AVX2 + FMA (explicit_kernels.h)
  std::vector<Sym3> preconditioner_;     ///< block Jacobi: (A_ii)⁻¹ per vertex (0 at fixed)
  std::vector<Real> diagonal_mass_;      ///< m_i (1 + hγ) + h² k_home, for this step's h
  std::vector<Vec3> volume_gradient_;    ///< ∇V at this step's positions (m²)
  std::vector<CachedSpring> spring_cache_;      ///< per spring, rebuilt once per implicit step
  std::vector<CachedTriangle> triangle_cache_;  ///< per triangle (when the area term is on)
  std::vector<Real> free_;               ///< 1 for free vertices, 0 for fixed (the filter S)
  std::vector<std::uint32_t> fixed_indices_;  ///< the fixed vertices
  std::vector<Vec3> fixed_positions_;    ///< their positions at the start of a step
};

}  // namespace trocar

#pragma once
/// Extended position-based dynamics with substeps (XPBD): the mass-spring tissue's springs, area
/// and volume terms as compliant constraints, solved one Gauss–Seidel pass per substep
/// (Macklin, Müller, Chentanez, "XPBD: position-based simulation of compliant constrained
/// dynamics", MIG 2016; Macklin et al., "Small steps in physics simulation", SCA 2019), with
/// contact solved inside every substep by a handler (response/solver_contact.h).
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"

namespace trocar {
namespace tissue_detail {
struct XpbdSpringColour;
}

/// One particle as the solver holds it: position (m, float) and inverse mass (1/kg; 0 = does not
/// move). 16 bytes, so one aligned load reads a vertex.
struct alignas(16) XpbdParticle {
  float x = 0, y = 0, z = 0;
  float w = 0;  ///< inverse mass
};

/// What a contact handler sees of the solver during a substep.
struct XpbdView {
  std::span<XpbdParticle> x;               ///< positions now (the handler moves free ones in place)
  std::span<const XpbdParticle> previous;  ///< positions at the start of this substep
  std::span<const Real> masses;            ///< m_i (kg)
  std::span<const Triangle> triangles;     ///< the tissue's outward surface
};

/// Contact inside the solver: called once before the substeps and once at the end of each
/// substep, after the internal constraints, so a vertex ends every substep outside the
/// instruments. Implementations must not allocate in these calls after their first step.
class XpbdContacts {
 public:
  virtual ~XpbdContacts() = default;
  /// Before the substeps, with the step's start positions: find candidates, grasp or release.
  virtual void begin_step(const XpbdView& view, int substeps) = 0;
  /// Substep `substep` of `substeps` (0-based), of length h (s): project the contacts.
  virtual void solve(const XpbdView& view, int substep, int substeps, Real h) = 0;
  /// After the substep's velocities v = (x − x_start)/h: the contacts' velocity pass (an
  /// inelastic contact keeps no separating speed from its position correction; Müller et al.
  /// 2020 §3.6).
  /// `velocities` holds v in each particle's x, y, z.
  virtual void solve_velocities(std::span<XpbdParticle> velocities) = 0;
};

/// Options of the XPBD solver (scene key `solver`, docs/tissue.md "XPBD").
struct XpbdOptions {
  /// Substeps per step, one constraint pass each ("Small steps": more substeps beat more
  /// iterations for the same cost). ≥ 1.
  int substeps = 4;
};

/// What one XPBD step measured.
struct XpbdStats {
  /// The largest |C| over the springs in the last substep's pass (before its correction),
  /// relative to the rest length: with soft springs it is the springs' real strain.
  Real max_strain = 0;
};

/// Steps one tissue with XPBD. Built once from the settings; step() never allocates.
///
/// Constraints and their compliance α (the inverse of the stiffness the energy gives, so a
/// scene means the same organ under every integrator: tissue/forces.h):
///  - each spring (structural and bending): C = |x_i − x_j| − l_ij, α = 1/k_ij; its damping
///    λ_ij (N·s/m) as an implicit dashpot on the velocities once per step (xpbd_kernels.h).
///    XPBD's own damping term (eq. 26) was measured and dropped: it also resists the substep's
///    gravity prediction, so it softens the static shape (a hanging sheet sagged 6.6 % more);
///  - each triangle (k_area > 0): C = A − A0, α = Ā0 / k_area (energy ½ k_area (A − A0)²/Ā0);
///  - the volume (closed, k_volume > 0): C = V − V0, α = V0 / k_volume;
///  - home springs (k_home > 0): C = |x − x0|, α = 1/k_home.
/// Each substep: v ← (v + h (g + f/m)) / (1 + hγ) (the mass-proportional damping γ implicitly);
/// x ← x + h v; one pass over the springs in colour order (no two springs of a colour share a
/// vertex), the triangles in colour order, the volume (last substep only, see step()), the home
/// springs; then the contact
/// handler; v ← (x − x_start)/h and the handler's velocity pass. After the substeps, the
/// dashpots. The Lagrange multipliers start at zero each substep (one iteration: "Small steps"
/// §4).
class XpbdSolver {
 public:
  XpbdSolver(const MassSpringSettings& settings, XpbdOptions options = {});

  /// Advances `state` by dt (s) under the constraints, gravity, `loads`' forces (their Jacobians
  /// are not used) and, when given, the contact handler. Fixed vertices keep their position bit
  /// for bit and zero velocity.
  XpbdStats step(MassSpringState& state, const TissueLoads& loads, Real dt, XpbdContacts* contacts);

  /// step() in its phases, for tissues stepped in lock-step with constraints between them solved
  /// inside their substeps (response/tissue_contact.h, coupled): begin(); per substep s,
  /// substep_constraints(s) (predict, the tissue's own constraints), substep_contacts(s) (the
  /// instrument handler), substep_velocities() (v = Δx/h and the handler's velocity pass);
  /// finish(). `substeps` replaces the options' count for this step. step() is exactly these.
  void begin(MassSpringState& state, const TissueLoads& loads, Real dt, XpbdContacts* contacts, int substeps);
  void substep_constraints(int s);
  void substep_contacts(int s);
  void substep_velocities();
  XpbdStats finish(MassSpringState& state);
  /// Between begin() and finish(): the particles as the solver holds them (positions, the
  /// substep's start), and their velocities (m/s in x, y, z) after substep_velocities().
  XpbdView view();
  std::span<XpbdParticle> velocities() { return std::span(v_).first(v_.size() - 1); }
  /// The substep length of the step under way (s).
  Real substep_length() const { return run_.h; }

  const XpbdOptions& options() const { return options_; }
  void set_substeps(int substeps) { options_.substeps = substeps < 1 ? 1 : substeps; }
  /// The settings' springs `springs` (indices) changed stiffness, rest length or damping (a
  /// coagulated patch): copies them again. No allocation.
  void springs_changed(std::span<const std::uint32_t> springs);
  /// Whether the AVX2 passes run (default: where the CPU has AVX2 + FMA); off runs the scalar
  /// passes, which give the same result to float rounding.
  void set_simd(bool on);
  bool simd() const { return avx2_; }

 private:
  void solve_springs(float inv_h2, bool last);
  void damp_springs(float h);
  tissue_detail::XpbdSpringColour spring_colour(std::size_t c) const;
  void solve_triangles(float inv_h2);
  void solve_volume(float inv_h_dt);
  void solve_home(float inv_h2);

  const MassSpringSettings& settings_;
  XpbdOptions options_;
  /// The step under way (begin() to finish()).
  struct Run {
    const TissueLoads* loads = nullptr;
    XpbdContacts* contacts = nullptr;
    Real dt = 0;
    int substeps = 1, substep = 0;
    float h = 0, inv_h = 0, damp = 1;
  };
  Run run_;
  bool avx2_ = false;                         ///< the CPU has AVX2 + FMA: the 8-lane passes
  /// Particles: the vertices, then one padding particle (inverse mass 0) that the padding
  /// springs and triangles of each colour join to itself.
  std::vector<XpbdParticle> x_, previous_;
  /// False until the first step: previous_ then comes from the state (x − v h), not the rest shape,
  /// so a solver built for a deformed, moving tissue (a cut's rebuild) starts with its true motion.
  bool primed_ = false;
  std::vector<XpbdParticle> v_;               ///< velocities (m/s) in x, y, z (w unused)
  std::vector<float> inverse_masses_;         ///< from the settings (0 at fixed vertices)
  // Springs with a stiffness, colour by colour, each colour padded to a multiple of 8.
  std::vector<std::uint32_t> spring_i_, spring_j_;
  std::vector<float> spring_rest_, spring_compliance_, spring_damping_;
  std::vector<std::size_t> spring_colour_start_;
  std::vector<std::uint32_t> slot_of_spring_;  ///< per settings spring: its slot above (UINT32_MAX: not solved)
  // Triangles of the area term, the same way.
  std::vector<std::uint32_t> triangle_v0_, triangle_v1_, triangle_v2_;
  std::vector<float> triangle_rest_;
  std::vector<std::size_t> triangle_colour_start_;
  std::vector<float> volume_gradient_;        ///< ∂(6V)/∂x_i, 3 per vertex (volume term)
  std::vector<std::uint32_t> fixed_;          ///< fixed vertex ids
  std::vector<Vec3> fixed_positions_;
  float area_compliance_ = 0;                 ///< Ā0 / k_area (0: off)
  double volume_compliance_ = 0;              ///< V0 / k_volume (0: off)
  float home_compliance_ = 0;                 ///< 1/k_home (0: off)
  Real max_strain_ = 0;
};

/// Greedy colouring of `items` (each a set of `arity` vertex ids) so that no two items of a
/// colour share a vertex: items are visited in order and take the lowest colour none of their
/// vertices has yet. Returns each item's colour; `colour_count` gets the number of colours.
std::vector<std::uint32_t> colour_items(std::span<const std::uint32_t> vertex_ids, std::size_t arity,
                                        std::size_t vertex_count, std::size_t& colour_count);

}  // namespace trocar

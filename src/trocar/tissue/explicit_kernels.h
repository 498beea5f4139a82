#pragma once
/// The explicit integrators' hot passes over a padded layout, with an AVX2+FMA version chosen
/// at run time (the library is built for baseline x86-64; the AVX2 code is compiled per
/// function and only runs where the CPU has it). Internal to the tissue module.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/cpu_features.h"
#include "trocar/core/types.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"

namespace trocar::tissue_detail {

/// A 3-vector padded to 32 bytes (w stays 0), so it loads, and a force accumulates, with one
/// aligned 256-bit access instead of three scalar ones.
struct alignas(32) Padded3 {
  Real x = 0, y = 0, z = 0, w = 0;
};

/// `count` arrays of n padded vectors in one block, each starting 13 × 32 bytes further modulo
/// 4 KiB than the one before. Same-size arrays from separate allocations start at the same
/// offset in their page once they are large enough to be mmap'ed, and then a load of x[j] just
/// after a store to f[j] looks to the CPU like a dependence on that store ("4K aliasing";
/// measured: an implicit step on a Morton-ordered gallbladder 673 → 501 ns/vertex).
class PaddedArrays {
 public:
  /// Zeroed arrays; earlier spans are invalidated.
  void allocate(std::size_t n, std::size_t count);
  std::span<Padded3> operator[](std::size_t k) { return {storage_.data() + k * stride_, n_}; }

 private:
  std::vector<Padded3> storage_;
  std::size_t n_ = 0, stride_ = 0;
};

/// Throws trocar::Error unless `vertex_count` vertices fit the padded layout: the byte offsets
/// (index × 32) the spring quads and fans store are 32-bit; the layout takes fewer than 2^27.
void check_padded_vertex_count(std::uint64_t vertex_count);

/// f_i += the loads' external force at each vertex the step loaded (TissueLoads records them),
/// for n vertices; nothing when the loads are not sized for n (never reset: no forces).
/// Inline, so that each caller (the AVX2 implicit step is one) compiles it for its own target.
inline void add_external_forces(const TissueLoads& loads, Padded3* f, std::size_t n) {
  const std::span<const Vec3> external = loads.forces();
  if (external.size() != n) return;
  for (const std::uint32_t i : loads.loaded_vertices()) {
    f[i].x += external[i].x();
    f[i].y += external[i].y();
    f[i].z += external[i].z();
  }
}

/// Four springs' data lane by lane (structure of arrays), so the AVX2 pass loads each parameter
/// of four springs at once. 128 bytes, the size of four Spring records. The endpoints are byte
/// offsets into a Padded3 array (index × 32), so addressing needs no shift.
struct alignas(32) SpringQuad {
  std::uint32_t i[4] = {};  ///< first vertex × sizeof(Padded3)
  std::uint32_t j[4] = {};  ///< second vertex × sizeof(Padded3)
  Real rest_length[4] = {};
  Real stiffness[4] = {};
  Real damping[4] = {};
};

/// The springs in quads, in order; the last quad is completed with null springs (vertex 0 to
/// itself, k = λ = 0), which add exactly zero.
std::vector<SpringQuad> make_spring_quads(const std::vector<Spring>& springs);

/// The springs as quads whose four springs share their first vertex (stars: x_i, v_i load once
/// and f_i is written once) and ordinary quads for the rest.
struct SpringLayout {
  std::vector<SpringQuad> stars;
  std::vector<SpringQuad> others;
  /// Per spring of a layout made without `fixed`: where it went, 4 × quad + lane, with kInOthers
  /// set for `others` (set_spring_constants uses it).
  std::vector<std::uint32_t> where;
  static constexpr std::uint32_t kInOthers = 1u << 31;
};
/// Copies spring s's rest length, stiffness and damping into the layout, in place (its vertices
/// are unchanged). For a layout made without `fixed`. No allocation.
void set_spring_constants(SpringLayout& layout, std::size_t s, const Spring& spring);
/// With `fixed` (1 per fixed vertex), the springs between two fixed vertices are left out: their
/// forces only act on vertices that never move (on the liver bench, 5 % of the springs).
SpringLayout make_spring_layout(const std::vector<Spring>& springs, std::size_t vertex_count,
                                const std::vector<std::uint8_t>* fixed = nullptr);

/// out_i = (p_i, 0) for n vectors.
void copy_padded(const Vec3* p, std::size_t n, Padded3* out);

/// f_i += the spring forces on i (eq. 3.2; forces.cpp's spring_forces) at positions x and
/// velocities v (padded copies of the state).
void add_spring_forces(const SpringLayout& layout, const Padded3* x, const Padded3* v, Padded3* f, bool use_avx2);

/// forces.cpp's scalar area pass into the padded layout (nothing when the area term is off).
void add_area_forces(const MassSpringSettings& s, const Vec3* x, Padded3* f);

/// Σ ½ k (|x_j − x_i| − l)² over the springs of `layout` (forces.cpp's spring_energy; null
/// springs add 0).
Real spring_energy_padded(const SpringLayout& layout, const Padded3* x, bool use_avx2);

/// 6V about the first triangle's first vertex (forces.cpp's volume_of × 6).
Real six_volume_padded(const MassSpringSettings& s, const Padded3* x, bool use_avx2);

/// The per-vertex update of one explicit step, with the per-vertex forces folded in:
///   f = f_pair + pressure6 · g + m (gravity − γ v) − k_home (x − x0)
/// (the external forces are added into f_pair beforehand, at the loaded vertices only),
///   v₁ = v + h f / m,  x₁ = x + h (symplectic ? v₁ : v).
/// Reads and then zeroes `pair` (and `gradient` when not null), so both are zero again for the
/// next step without a separate clearing pass.
struct UpdateInputs {
  const Padded3* x = nullptr;       ///< positions at the start of the step (padded copy)
  const Padded3* v = nullptr;       ///< velocities at the start of the step (padded copy)
  const Padded3* rest = nullptr;    ///< rest positions x0 (padded)
  Padded3* pair = nullptr;          ///< spring, area and external forces (zeroed on return)
  Padded3* gradient = nullptr;      ///< Σ n_t per vertex, or null (zeroed on return)
  Real pressure6 = 0;               ///< −κ_V (V − V0)/6
  Vec3 gravity = Vec3::Zero();
  Real gamma = 0;                   ///< global damping γ (1/s)
  Real k_home = 0;                  ///< N/m
  Real dt = 0;
  bool symplectic = true;
};
/// Writes x₁, v₁ into x, v (the state in.x, in.v were copied from); returns Σ of every coordinate of x₁ and v₁ (non-finite iff some
/// coordinate is).
Real explicit_update(const MassSpringSettings& s, Vec3* x, Vec3* v, const UpdateInputs& in, bool use_avx2);

}  // namespace trocar::tissue_detail

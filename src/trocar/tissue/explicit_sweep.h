#pragma once
/// The explicit steps' AVX2 passes (explicit_kernels.h, volume_fans.h) fused into one sweep over
/// blocks of vertices, so that a vertex's padded copies stay in L1/L2 from the first spring that
/// reads them to its update. Internal to the tissue module.
///
/// Why: the pass-by-pass step streams ~700 bytes per vertex through five full-size padded arrays.
/// On the liver (2,194 vertices) they fit in the 2 MB L2; on the gallbladder (7,352) and the
/// abdominal wall (15,969) every pass reads them from L3, and the update pass alone took 7.7 ns
/// per vertex on the abdominal wall against 3.2 on the liver.
///
/// How: every spring quad is given to the block of its lowest vertex. With the vertices in a
/// banded order (mesh/renumber.h), block b's quads only touch vertices in [b·S, b·S + S + span).
/// Before block b runs, the vertices up to its highest one are copied into ring buffers of W
/// slots (vertex i in slot i mod W: position, velocity and a zeroed force); after its springs,
/// block b's own vertices have every spring force they will get (later blocks' quads start at
/// higher vertices) and are updated from the ring. W is the largest live range (copied, not yet
/// updated), so a slot is reused only after its vertex was updated; the quads' offsets are
/// precomputed as slots. A mesh without a banded order only makes W larger (up to V).
///
/// The volume pressure needs V before any vertex is updated, so the volume pass runs first, as in
/// the pass-by-pass step, reading the state's positions directly; the update reads its Σ n_t.
/// (Computing the gradient inside the sweep and 6V in a pre-pass was slower: the normals were
/// computed twice.) The area term is not in the sweep: the pass-by-pass step runs when it is on.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/tissue/explicit_kernels.h"
#include "trocar/tissue/forces.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"
#include "trocar/tissue/volume_fans.h"

namespace trocar::tissue_detail {

/// A star quad (four springs sharing their first vertex) in one cache line, for springs of at
/// most two (k, λ) classes, as MassSpringSettings::build makes them (structural and bending):
/// lane k's class is bit k of `classes`, and the stiffnesses and dampings are looked up in the
/// plan's tables. SpringQuad takes 128 bytes for the same springs.
struct alignas(64) StarQuad {
  std::uint32_t i[1] = {};    ///< the shared first vertex (slot × 32)
  std::uint32_t classes = 0;  ///< bit k: lane k's spring is of class 1
  std::uint32_t j[4] = {};    ///< second vertices (slots × 32)
  alignas(32) Real rest_length[4] = {};  ///< at byte 32: one aligned 256-bit load
};
static_assert(sizeof(StarQuad) == 64, "a StarQuad is one cache line");

/// The blocked layout (built once) and the ring buffers (scratch of every step).
struct SweepPlan {
  /// Where block b's items end in each list, and the vertex the copies reach before it runs.
  struct Block {
    std::uint32_t stars_end, others_end, copy_end;
  };
  std::size_t block = 0, window = 0;
  std::vector<SpringQuad> stars, others;  ///< offsets are slots × 32 (stars empty when compact)
  std::vector<StarQuad> compact_stars;    ///< the stars when their springs have ≤ 2 classes
  /// Per classes mask (0–15), the four lanes' stiffness and damping (compact stars).
  alignas(32) Real class_stiffness[16][4] = {}, class_damping[16][4] = {};
  std::vector<Block> blocks;
  VolumeLayout volume;    ///< in vertex offsets (empty: the mesh has no volume term)
  PaddedArrays ring;      ///< x, v, f: W slots each
  PaddedArrays gradient;  ///< Σ_{t∋i} n_t, V of them (zeroed by the update that reads them)
  std::vector<std::uint32_t> loaded;  ///< this step's loaded vertices, sorted (capacity V)
};

/// Whether the sweep should replace the pass-by-pass step for `s`: when the pass-by-pass step's
/// arrays (five padded copies, the state, masses, springs, fans) exceed the L2 cache (the OS's
/// figure, else 1 MiB). Measured in docs/tissue-integrators.md, "The sweep": on the liver
/// (0.9 MB) the passes are faster, on the gallbladder (3.1 MB) and the abdominal wall (6.7 MB)
/// the sweep is.
bool sweep_pays(const MassSpringSettings& s);
/// The bytes sweep_pays compares with the L2 cache.
std::size_t pass_by_pass_bytes(const MassSpringSettings& s);

class ExplicitSweep {
 public:
  /// Vertices per block by default (measured: docs/tissue-integrators.md, "The sweep").
  static constexpr std::size_t kDefaultBlock = 256;

  /// The layouts of `s` (springs between two fixed vertices left out, as make_spring_layout)
  /// cut into blocks of `block` vertices. Keeps a reference to `s`, which must outlive the sweep
  /// (as MassSpringIntegrator's). Throws trocar::Error as the layouts do, or for block 0.
  explicit ExplicitSweep(const MassSpringSettings& s, std::size_t block = kDefaultBlock);

  /// One explicit step of x, v (the state's arrays, V each) with the terms of `terms` except the
  /// area term: v₁ = v + h M⁻¹ (f(x, v) + the loads' forces), x₁ = x + h (symplectic ? v₁ : v),
  /// as explicit_update after the passes. Returns Σ of every coordinate of x₁ and v₁. Only
  /// where the CPU has AVX2+FMA (cpu_has_avx2_fma()); never allocates.
  Real step(Vec3* x, Vec3* v, const TissueLoads& loads, const ForceTerms& terms, Real dt, bool symplectic);

  std::size_t block() const { return plan_.block; }
  std::size_t window() const { return plan_.window; }  ///< W: ring slots (≤ V)
  const SweepPlan& plan() const { return plan_; }

 private:
  const MassSpringSettings& settings_;
  SweepPlan plan_;
};

}  // namespace trocar::tissue_detail

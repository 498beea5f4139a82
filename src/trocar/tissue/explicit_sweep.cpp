// The explicit step as one sweep over blocks of vertices (explicit_sweep.h): building the blocked
// layout, and the AVX2 step over ring buffers. The formulas and kernels are explicit_kernels.h's
// and volume_fans.h's; only the order of the work differs.
#include "trocar/tissue/explicit_sweep.h"

#include <algorithm>
#include <string>

#include <unistd.h>

#include "trocar/core/cpu_features.h"
#include "trocar/core/error.h"
#include "trocar/tissue/avx2.h"
#include "trocar/tissue/spring_blocks.h"

namespace trocar::tissue_detail {
namespace {

constexpr std::uint32_t kStride = sizeof(Padded3);

/// Vertex offsets (index × 32) or indices → ring slots (index mod W).
std::uint32_t slot_offset(std::uint32_t offset, std::size_t window) {
  return static_cast<std::uint32_t>(offset / kStride % window * kStride);
}
void to_slots(SpringQuad& q, std::size_t window) {
  for (int k = 0; k < 4; ++k) {
    q.i[k] = slot_offset(q.i[k], window);
    q.j[k] = slot_offset(q.j[k], window);
  }
}
/// The stars as StarQuads when all their springs have one of at most two (k, λ) classes (then
/// the plan's tables are filled and `stars` emptied); otherwise nothing changes.
void compact_stars(SweepPlan& p) {
  Real k[2] = {}, lambda[2] = {};
  int classes = 0;
  const auto class_of = [&](Real stiffness, Real damping) {
    for (int c = 0; c < classes; ++c)
      if (k[c] == stiffness && lambda[c] == damping) return c;
    if (classes == 2) return -1;
    k[classes] = stiffness;
    lambda[classes] = damping;
    return classes++;
  };
  std::vector<StarQuad> compact(p.stars.size());
  for (std::size_t q = 0; q < p.stars.size(); ++q) {
    const SpringQuad& s = p.stars[q];
    StarQuad& c = compact[q];
    c.i[0] = s.i[0];
    for (int lane = 0; lane < 4; ++lane) {
      const int cls = class_of(s.stiffness[lane], s.damping[lane]);
      if (cls < 0) return;  // three classes or more: keep the SpringQuads
      c.classes |= static_cast<std::uint32_t>(cls) << lane;
      c.j[lane] = s.j[lane];
      c.rest_length[lane] = s.rest_length[lane];
    }
  }
  for (int mask = 0; mask < 16; ++mask)
    for (int lane = 0; lane < 4; ++lane) {
      p.class_stiffness[mask][lane] = k[(mask >> lane) & 1];
      p.class_damping[mask][lane] = lambda[(mask >> lane) & 1];
    }
  p.compact_stars = std::move(compact);
  p.stars.clear();
  p.stars.shrink_to_fit();
}

#ifdef TROCAR_HAVE_X86
using namespace avx2;

/// A StarQuad's parameters: its rest lengths, and its classes' row of the plan's tables.
struct ClassParameters {
  const SweepPlan* plan;
  TROCAR_AVX2 QuadParameters operator()(const StarQuad& s) const {
    return {_mm256_load_pd(s.rest_length), _mm256_load_pd(plan->class_stiffness[s.classes]),
            _mm256_load_pd(plan->class_damping[s.classes])};
  }
};

TROCAR_AVX2 Real sweep_avx2(SweepPlan& p, const MassSpringSettings& s, Vec3* x, Vec3* v, const TissueLoads& loads,
                            const ForceTerms& terms, Real dt, bool symplectic) {
  const std::size_t n = s.vertex_count(), window = p.window;
  Padded3* rx = p.ring[0].data();
  Padded3* rv = p.ring[1].data();
  Padded3* rf = p.ring[2].data();
  Padded3* g = p.gradient[0].data();

  const bool volume = volume_term_on(s, terms) && !(p.volume.fans.empty() && p.volume.singles.empty());
  Real pressure6 = 0;
  if (volume) {  // −κ_V (V − V0)/6, as the pass-by-pass step
    const Real six_v = volume_gradient(p.volume, StateLoad{x}, g);
    pressure6 = -s.k_volume / s.rest_volume * (six_v / 6.0 - s.rest_volume) / 6.0;
  }
  const Vec3 gravity = terms.gravity ? s.gravity : Vec3::Zero();
  const Real k_home = terms.home ? s.k_home : 0.0;
  UpdateConstants c;
  c.gravity = _mm256_setr_pd(gravity[0], gravity[1], gravity[2], 0);
  c.gamma = _mm256_set1_pd(terms.global_damping ? s.damping : 0.0);
  c.k_home = _mm256_set1_pd(k_home);
  c.dt = _mm256_set1_pd(dt);
  c.symplectic = symplectic;
  const bool home = k_home != 0;
  const __m256d pressure = _mm256_set1_pd(pressure6);

  // The loaded vertices in order, so each block adds the forces of the vertices it copies.
  const std::span<const Vec3> external = loads.forces();
  p.loaded.clear();
  if (external.size() == n) {
    p.loaded.insert(p.loaded.end(), loads.loaded_vertices().begin(), loads.loaded_vertices().end());
    std::sort(p.loaded.begin(), p.loaded.end());
  }

  const Real* mass = s.masses.data();
  const Real* inverse_mass = s.inverse_masses.data();
  const Vec3* rest = s.home_positions.data();
  const __m256d zero = _mm256_setzero_pd();
  __m256d check = zero;
  std::size_t copied = 0, copy_slot = 0, update_slot = 0, next_load = 0;
  std::uint32_t stars = 0, others = 0;
  for (std::size_t b = 0; b < p.blocks.size(); ++b) {
    const SweepPlan::Block& block = p.blocks[b];
    for (; copied < block.copy_end; ++copied) {
      store(rx[copy_slot], load3(x[copied]));
      store(rv[copy_slot], load3(v[copied]));
      store(rf[copy_slot], zero);
      if (++copy_slot == window) copy_slot = 0;
    }
    for (; next_load < p.loaded.size() && p.loaded[next_load] < copied; ++next_load) {
      const std::uint32_t i = p.loaded[next_load];
      Padded3& f = rf[i % window];
      f.x += external[i].x();
      f.y += external[i].y();
      f.z += external[i].z();
    }
    if (terms.springs) {
      if (p.stars.empty())
        add_quad_spring_forces<true>(p.compact_stars.data() + stars, block.stars_end - stars, ClassParameters{&p}, rx,
                                     rv, rf);
      else
        add_quad_spring_forces<true>(p.stars.data() + stars, block.stars_end - stars, OwnParameters{}, rx, rv, rf);
      add_quad_spring_forces<false>(p.others.data() + others, block.others_end - others, OwnParameters{}, rx, rv, rf);
    }
    stars = block.stars_end;
    others = block.others_end;

    // Block b's vertices have all their forces now: update them (explicit_update's formula).
    const std::size_t end = std::min(n, (b + 1) * p.block);
    for (std::size_t i = b * p.block; i < end; ++i) {
      const std::size_t k = update_slot;
      if (++update_slot == window) update_slot = 0;
      const __m256d xi = load(rx[k]);
      __m256d f = load(rf[k]);
      if (volume) {
        f = _mm256_fmadd_pd(pressure, load(g[i]), f);
        store(g[i], zero);
      }
      // Without home springs x0 = x, so the k_home term is an exact zero and the rest positions
      // are not read.
      const __m256d x0 = home ? load3(rest[i]) : xi;
      check = _mm256_add_pd(check, explicit_vertex_update(c, f, xi, load(rv[k]), x0, mass[i], inverse_mass[i], x[i], v[i]));
    }
  }
  return sum_xyz(check);
}
#endif  // TROCAR_HAVE_X86

}  // namespace

std::size_t pass_by_pass_bytes(const MassSpringSettings& s) {
  // Per vertex: x, v, forces, Σ n_t and rest padded (5 × 32), the state's x and v (2 × 24), m and
  // 1/m (16); per spring 32 (SpringQuad); per triangle 6 (a fan is 24 bytes for four).
  return s.vertex_count() * (5 * sizeof(Padded3) + 2 * sizeof(Vec3) + 2 * sizeof(Real)) +
         s.springs.size() * sizeof(Spring) + s.triangles.size() * sizeof(TriangleFan) / 4;
}

bool sweep_pays(const MassSpringSettings& s) {
  long l2 = -1;
#ifdef _SC_LEVEL2_CACHE_SIZE
  l2 = sysconf(_SC_LEVEL2_CACHE_SIZE);
#endif
  const std::size_t cache = l2 > 0 ? static_cast<std::size_t>(l2) : std::size_t{1} << 20;
  return pass_by_pass_bytes(s) > cache;
}

ExplicitSweep::ExplicitSweep(const MassSpringSettings& s, std::size_t block) : settings_(s) {
  const std::size_t n = s.vertex_count();
  SweepPlan& p = plan_;
  p.block = block;
  if (s.closed && s.k_volume > 0) p.volume = make_volume_layout(s.triangles, n);
  BlockedSprings springs = block_springs(make_spring_layout(s.springs, n, &s.fixed), n, block);
  p.stars = std::move(springs.layout.stars);
  p.others = std::move(springs.layout.others);

  // The copies run ahead to each block's reach; W is the most vertices live at once (copied,
  // not yet updated), so slot i mod W is free again by the time vertex i + W is copied.
  const std::size_t blocks = springs.reach.size();
  p.blocks.resize(blocks);
  p.window = 1;
  for (std::size_t b = 0; b < blocks; ++b) {
    p.window = std::max<std::size_t>(p.window, springs.reach[b] - b * block);
    p.blocks[b] = {springs.stars_end[b], springs.others_end[b], springs.reach[b]};
  }
  for (SpringQuad& q : p.stars) to_slots(q, p.window);
  for (SpringQuad& q : p.others) to_slots(q, p.window);
  compact_stars(p);
  p.ring.allocate(p.window, 3);
  p.gradient.allocate(p.volume.fans.empty() && p.volume.singles.empty() ? 0 : n, 1);
  p.loaded.reserve(n);
}

Real ExplicitSweep::step(Vec3* x, Vec3* v, const TissueLoads& loads, const ForceTerms& terms, Real dt,
                         bool symplectic) {
#ifdef TROCAR_HAVE_X86
  if (cpu_has_avx2_fma()) return sweep_avx2(plan_, settings_, x, v, loads, terms, dt, symplectic);
#endif
  (void)x, (void)v, (void)loads, (void)terms, (void)dt, (void)symplectic;
  throw Error("tissue: the explicit sweep needs a CPU with AVX2 and FMA");
}

}  // namespace trocar::tissue_detail

// The explicit integrators' passes: springs, per-vertex update (the volume pass is in
// volume_fans.cpp); scalar and AVX2+FMA. The formulas are forces.cpp's; only the arithmetic
// layout differs.
//
// Why this layout (measured on the shared liver, 2,194 V, 13,152 springs, one core): a scalar
// spring is ~80 instructions and the spring pass was two thirds of a semi-implicit step. Here
// the state is first copied into 32-byte padded vectors (x, y, z, 0), so each endpoint is one
// aligned 256-bit load and each force one aligned load-add-store; the spring parameters are
// stored four springs lane by lane (SpringQuad), so they load without shuffles; most quads are
// stars (four springs sharing their first vertex, loaded and written once); four springs' |d|²
// and Δv·d come from one transpose of d and w (avx2.h); σ is computed for four springs at once
// with one exact vsqrtpd and one vdivpd (a float rsqrt estimate plus Newton steps in double was
// no faster: the divider is not the bottleneck); and σ goes back to each spring by a broadcast
// load from a stack array (a load port) rather than a permute (the shuffle port). Spring pass
// 33.4 → 12.1 ns per vertex (docs/tissue-integrators.md, "The AVX2 passes").
#include "trocar/tissue/explicit_kernels.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "trocar/core/error.h"
#include "trocar/tissue/avx2.h"
#include "trocar/tissue/internal.h"

namespace trocar::tissue_detail {
namespace {

/// Lane k of a quad, scalar (forces.cpp's spring_forces body).
inline void spring_scalar(const SpringQuad& q, int k, const Padded3* x, const Padded3* v, Padded3* f) {
  const std::uint32_t i = q.i[k] / sizeof(Padded3), j = q.j[k] / sizeof(Padded3);
  const Padded3 &xi = x[i], &xj = x[j], &vi = v[i], &vj = v[j];
  const Real dx = xj.x - xi.x, dy = xj.y - xi.y, dz = xj.z - xi.z;
  const Real wx = vj.x - vi.x, wy = vj.y - vi.y, wz = vj.z - vi.z;
  const Real len2 = dx * dx + dy * dy + dz * dz;
  const Real inv = len2 > kTinyLength2 ? 1.0 / std::sqrt(len2) : 0.0;
  const Real len = len2 * inv;
  const Real sigma =
      q.stiffness[k] * (len - q.rest_length[k]) * inv + q.damping[k] * (wx * dx + wy * dy + wz * dz) * inv * inv;
  Padded3 &fi = f[i], &fj = f[j];
  fi.x += sigma * dx;
  fi.y += sigma * dy;
  fi.z += sigma * dz;
  fj.x -= sigma * dx;
  fj.y -= sigma * dy;
  fj.z -= sigma * dz;
}

/// Lane k's energy ½ k (|d| − l)², scalar.
inline Real spring_energy_scalar(const SpringQuad& q, int k, const Padded3* x) {
  const Padded3 &xi = x[q.i[k] / sizeof(Padded3)], &xj = x[q.j[k] / sizeof(Padded3)];
  const Real dx = xj.x - xi.x, dy = xj.y - xi.y, dz = xj.z - xi.z;
  const Real stretch = std::sqrt(dx * dx + dy * dy + dz * dz) - q.rest_length[k];
  return 0.5 * q.stiffness[k] * stretch * stretch;
}

Real six_volume_scalar(const Triangle* tris, std::size_t nt, const Padded3* x) {
  const Padded3 origin = x[tris[0][0]];
  Real six_v = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    const Padded3 &a = x[tris[t][0]], &b = x[tris[t][1]], &c = x[tris[t][2]];
    const Real e0 = b.x - a.x, e1 = b.y - a.y, e2 = b.z - a.z;
    const Real f0 = c.x - a.x, f1 = c.y - a.y, f2 = c.z - a.z;
    six_v += (a.x - origin.x) * (e1 * f2 - e2 * f1) + (a.y - origin.y) * (e2 * f0 - e0 * f2) +
             (a.z - origin.z) * (e0 * f1 - e1 * f0);
  }
  return six_v;
}

Real update_scalar(const MassSpringSettings& s, Vec3* x, Vec3* v, const UpdateInputs& in) {
  const std::size_t n = s.vertex_count();
  const Vec3* x0 = s.home_positions.data();
  Real check = 0;
  for (std::size_t i = 0; i < n; ++i) {
    Padded3& p = in.pair[i];
    Vec3 f(p.x, p.y, p.z);
    p = Padded3{};
    if (in.gradient != nullptr) {
      Padded3& g = in.gradient[i];
      f += in.pressure6 * Vec3(g.x, g.y, g.z);
      g = Padded3{};
    }
    const Vec3 xi = x[i], vi = v[i];
    f += s.masses[i] * (in.gravity - in.gamma * vi) - in.k_home * (xi - x0[i]);
    const Vec3 v1 = vi + (in.dt * s.inverse_masses[i]) * f;
    const Vec3 x1 = xi + in.dt * (in.symplectic ? v1 : vi);
    v[i] = v1;
    x[i] = x1;
    check += x1.sum() + v1.sum();
  }
  return check;
}

#ifdef TROCAR_HAVE_X86
using namespace avx2;

/// Σ ½ k (|d| − l)² for four springs at a time: d transposed into x, y, z rows, |d| by vsqrtpd.
template <bool kStar>
TROCAR_AVX2 __m256d spring_energy_avx2(const SpringQuad* quads, std::size_t count, const Padded3* x, __m256d sum) {
  for (std::size_t q = 0; q < count; ++q) {
    const SpringQuad& s = quads[q];
    __m256d d[4];
    if constexpr (kStar) {
      const __m256d xi = load_at(x, s.i[0]);
      for (int k = 0; k < 4; ++k) d[k] = _mm256_sub_pd(load_at(x, s.j[k]), xi);
    } else {
      for (int k = 0; k < 4; ++k) d[k] = _mm256_sub_pd(load_at(x, s.j[k]), load_at(x, s.i[k]));
    }
    __m256d dx, dy, dz;
    transpose_rows(d, dx, dy, dz);
    const __m256d len = _mm256_sqrt_pd(_mm256_fmadd_pd(dz, dz, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx))));
    const __m256d stretch = _mm256_sub_pd(len, _mm256_load_pd(s.rest_length));
    sum = _mm256_fmadd_pd(_mm256_mul_pd(_mm256_load_pd(s.stiffness), stretch), stretch, sum);
  }
  return sum;
}

TROCAR_AVX2 Real spring_energy_avx2(const SpringLayout& layout, const Padded3* x) {
  __m256d sum = spring_energy_avx2<true>(layout.stars.data(), layout.stars.size(), x, _mm256_setzero_pd());
  sum = spring_energy_avx2<false>(layout.others.data(), layout.others.size(), x, sum);
  return 0.5 * avx2::sum(sum);
}

TROCAR_AVX2 Real six_volume_avx2(const Triangle* tris, std::size_t nt, const Padded3* x) {
  const __m256d origin = load(x[tris[0][0]]);
  __m256d six_v = _mm256_setzero_pd();
  for (std::size_t t = 0; t < nt; ++t) {
    const __m256d a = load(x[tris[t][0]]);
    const __m256d n = cross(_mm256_sub_pd(load(x[tris[t][1]]), a), _mm256_sub_pd(load(x[tris[t][2]]), a));
    six_v = _mm256_fmadd_pd(_mm256_sub_pd(a, origin), n, six_v);
  }
  return sum_xyz(six_v);
}

TROCAR_AVX2 Real update_avx2(const MassSpringSettings& s, Vec3* x, Vec3* v, const UpdateInputs& in) {
  const std::size_t n = s.vertex_count();
  const Padded3* x0 = in.rest;
  const Real* mass = s.masses.data();
  const Real* inverse_mass = s.inverse_masses.data();
  UpdateConstants c;
  c.gravity = _mm256_setr_pd(in.gravity[0], in.gravity[1], in.gravity[2], 0);
  c.gamma = _mm256_set1_pd(in.gamma);
  c.k_home = _mm256_set1_pd(in.k_home);
  c.dt = _mm256_set1_pd(in.dt);
  c.symplectic = in.symplectic;
  const __m256d pressure6 = _mm256_set1_pd(in.pressure6);
  const __m256d zero = _mm256_setzero_pd();
  __m256d check = zero;
  for (std::size_t i = 0; i < n; ++i) {
    __m256d f = load(in.pair[i]);
    store(in.pair[i], zero);
    if (in.gradient != nullptr) {
      f = _mm256_fmadd_pd(pressure6, load(in.gradient[i]), f);
      store(in.gradient[i], zero);
    }
    check = _mm256_add_pd(check, explicit_vertex_update(c, f, load(in.x[i]), load(in.v[i]), load(x0[i]), mass[i],
                                                        inverse_mass[i], x[i], v[i]));
  }
  return sum_xyz(check);
}
TROCAR_AVX2 void copy_padded_avx2(const Vec3* p, std::size_t n, Padded3* out) {
  for (std::size_t i = 0; i < n; ++i) store(out[i], load3(p[i]));
}
#endif  // TROCAR_HAVE_X86

}  // namespace

void check_padded_vertex_count(std::uint64_t vertex_count) {
  constexpr std::uint64_t kLimit = std::uint64_t{1} << 27;  // 134,217,728
  if (vertex_count >= kLimit)
    throw Error("tissue: " + std::to_string(vertex_count) +
                " vertices are beyond the 134,217,727 the padded layout addresses");
}

namespace {
void check_offsets(const std::vector<Spring>& springs) {
  for (const Spring& sp : springs) check_padded_vertex_count(std::uint64_t{std::max(sp.i, sp.j)} + 1);
}
void put(SpringQuad& q, std::size_t k, const Spring& sp, bool flip) {
  q.i[k] = static_cast<std::uint32_t>((flip ? sp.j : sp.i) * sizeof(Padded3));
  q.j[k] = static_cast<std::uint32_t>((flip ? sp.i : sp.j) * sizeof(Padded3));
  q.rest_length[k] = sp.rest_length;
  q.stiffness[k] = sp.stiffness;
  q.damping[k] = sp.damping;
}
}  // namespace

std::vector<SpringQuad> make_spring_quads(const std::vector<Spring>& springs) {
  check_offsets(springs);
  std::vector<SpringQuad> quads((springs.size() + 3) / 4);
  for (std::size_t e = 0; e < springs.size(); ++e) put(quads[e / 4], e % 4, springs[e], false);
  return quads;
}

SpringLayout make_spring_layout(const std::vector<Spring>& all_springs, std::size_t vertex_count,
                                const std::vector<std::uint8_t>* fixed) {
  std::vector<Spring> moving;
  if (fixed != nullptr)
    for (const Spring& sp : all_springs)
      if (!((*fixed)[sp.i] && (*fixed)[sp.j])) moving.push_back(sp);
  const std::vector<Spring>& springs = fixed != nullptr ? moving : all_springs;
  check_offsets(springs);
  // Greedy: each vertex in turn takes its not yet placed springs four at a time (a spring's force
  // is symmetric in its ends, so it may be flipped to start at the shared vertex); whatever is
  // left over goes into ordinary quads, in the original order.
  std::vector<std::vector<std::uint32_t>> incident(vertex_count);
  for (std::size_t e = 0; e < springs.size(); ++e) {
    incident[springs[e].i].push_back(static_cast<std::uint32_t>(e));
    incident[springs[e].j].push_back(static_cast<std::uint32_t>(e));
  }
  std::vector<std::uint8_t> placed(springs.size(), 0);
  SpringLayout layout;
  layout.where.assign(springs.size(), 0);
  std::vector<std::uint32_t> open;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    open.clear();
    for (const std::uint32_t e : incident[v])
      if (!placed[e]) open.push_back(e);
    for (std::size_t k = 0; k + 4 <= open.size(); k += 4) {
      SpringQuad& q = layout.stars.emplace_back();
      for (std::size_t m = 0; m < 4; ++m) {
        const Spring& sp = springs[open[k + m]];
        put(q, m, sp, sp.i != v);
        placed[open[k + m]] = 1;
        layout.where[open[k + m]] = static_cast<std::uint32_t>(4 * (layout.stars.size() - 1) + m);
      }
    }
  }
  std::vector<Spring> rest;
  for (std::size_t e = 0; e < springs.size(); ++e)
    if (!placed[e]) {
      layout.where[e] = static_cast<std::uint32_t>(rest.size()) | SpringLayout::kInOthers;
      rest.push_back(springs[e]);
    }
  layout.others = make_spring_quads(rest);
  return layout;
}

void set_spring_constants(SpringLayout& layout, std::size_t s, const Spring& spring) {
  if (s >= layout.where.size()) return;
  const std::uint32_t w = layout.where[s];
  const std::uint32_t slot = w & ~SpringLayout::kInOthers;
  SpringQuad& q = (w & SpringLayout::kInOthers) ? layout.others[slot / 4] : layout.stars[slot / 4];
  q.rest_length[slot % 4] = spring.rest_length;
  q.stiffness[slot % 4] = spring.stiffness;
  q.damping[slot % 4] = spring.damping;
}

void PaddedArrays::allocate(std::size_t n, std::size_t count) {
  constexpr std::size_t kPerPage = 4096 / sizeof(Padded3);
  constexpr std::size_t kStagger = 13;  // Padded3s (416 bytes): 10 arrays land 416 bytes apart
  n_ = n;
  stride_ = (n + kPerPage - 1) / kPerPage * kPerPage + kStagger;
  storage_.assign(stride_ * count, Padded3{});
}

void copy_padded(const Vec3* p, std::size_t n, Padded3* out) {
#ifdef TROCAR_HAVE_X86
  if (cpu_has_avx2_fma()) return copy_padded_avx2(p, n, out);
#endif
  for (std::size_t i = 0; i < n; ++i) out[i] = Padded3{p[i][0], p[i][1], p[i][2], 0};
}

void add_spring_forces(const SpringLayout& layout, const Padded3* x, const Padded3* v, Padded3* f, bool use_avx2) {
#ifdef TROCAR_HAVE_X86
  if (use_avx2) {
    add_quad_spring_forces<true>(layout.stars.data(), layout.stars.size(), OwnParameters{}, x, v, f);
    add_quad_spring_forces<false>(layout.others.data(), layout.others.size(), OwnParameters{}, x, v, f);
    return;
  }
#endif
  (void)use_avx2;
  for (const std::vector<SpringQuad>* quads : {&layout.stars, &layout.others})
    for (const SpringQuad& q : *quads)
      for (int k = 0; k < 4; ++k) spring_scalar(q, k, x, v, f);
}

Real spring_energy_padded(const SpringLayout& layout, const Padded3* x, bool use_avx2) {
#ifdef TROCAR_HAVE_X86
  if (use_avx2) return spring_energy_avx2(layout, x);
#endif
  (void)use_avx2;
  Real e = 0;
  for (const std::vector<SpringQuad>* quads : {&layout.stars, &layout.others})
    for (const SpringQuad& q : *quads)
      for (int k = 0; k < 4; ++k) e += spring_energy_scalar(q, k, x);
  return e;
}

Real six_volume_padded(const MassSpringSettings& s, const Padded3* x, bool use_avx2) {
  if (s.triangles.empty()) return 0;
#ifdef TROCAR_HAVE_X86
  if (use_avx2) return six_volume_avx2(s.triangles.data(), s.triangles.size(), x);
#endif
  (void)use_avx2;
  return six_volume_scalar(s.triangles.data(), s.triangles.size(), x);
}

Real explicit_update(const MassSpringSettings& s, Vec3* x, Vec3* v, const UpdateInputs& in, bool use_avx2) {
#ifdef TROCAR_HAVE_X86
  if (use_avx2) return update_avx2(s, x, v, in);
#endif
  (void)use_avx2;
  return update_scalar(s, x, v, in);
}

}  // namespace trocar::tissue_detail

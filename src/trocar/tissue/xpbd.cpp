// XPBD with substeps (xpbd.h). The passes are Gauss–Seidel over float particles in colour order;
// within a colour no two constraints share a particle, so 8 run at once (xpbd_kernels.h).
#include "trocar/tissue/xpbd.h"

#include <algorithm>
#include <limits>
#include <cmath>

#include "trocar/core/cpu_features.h"
#include "trocar/core/error.h"
#include "trocar/tissue/xpbd_kernels.h"

namespace trocar {

std::vector<std::uint32_t> colour_items(std::span<const std::uint32_t> vertex_ids, std::size_t arity,
                                        std::size_t vertex_count, std::size_t& colour_count) {
  const std::size_t n = arity == 0 ? 0 : vertex_ids.size() / arity;
  std::vector<std::uint32_t> colour(n, 0);
  // used[v] is a bit set of the colours v's items have taken, 64 colours a word.
  std::size_t words = 1;
  std::vector<std::uint64_t> used(vertex_count * words, 0);
  colour_count = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t* ids = vertex_ids.data() + k * arity;
    std::size_t c = 0;
    for (;; ++c) {
      if (c / 64 >= words) {  // every colour so far is taken at some vertex: widen the sets
        std::vector<std::uint64_t> wider(vertex_count * (words + 1), 0);
        for (std::size_t v = 0; v < vertex_count; ++v)
          std::copy_n(used.begin() + static_cast<std::ptrdiff_t>(v * words), words,
                      wider.begin() + static_cast<std::ptrdiff_t>(v * (words + 1)));
        used.swap(wider);
        ++words;
      }
      bool free = true;
      for (std::size_t a = 0; a < arity && free; ++a)
        free = (used[ids[a] * words + c / 64] >> (c % 64) & 1u) == 0;
      if (free) break;
    }
    for (std::size_t a = 0; a < arity; ++a) used[ids[a] * words + c / 64] |= std::uint64_t{1} << (c % 64);
    colour[k] = static_cast<std::uint32_t>(c);
    colour_count = std::max(colour_count, c + 1);
  }
  return colour;
}

XpbdSolver::XpbdSolver(const MassSpringSettings& settings, XpbdOptions options)
    : settings_(settings), options_(options) {
  if (options_.substeps < 1) throw Error("xpbd: substeps must be at least 1");
  const std::size_t n = settings.vertex_count();
  x_.resize(n + 1);
  previous_.resize(n + 1);
  v_.resize(n + 1);
  inverse_masses_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& r = settings.rest_positions[i];
    previous_[i] = {static_cast<float>(r.x()), static_cast<float>(r.y()), static_cast<float>(r.z()), 0.f};
    inverse_masses_[i] = settings.fixed[i] ? 0.f : static_cast<float>(settings.inverse_masses[i]);
    if (settings.fixed[i]) fixed_.push_back(static_cast<std::uint32_t>(i));
  }
  fixed_positions_.resize(fixed_.size());

  // Springs with a stiffness, coloured; each colour sorted by its first vertex (memory order)
  // and padded to a multiple of 8 with springs from the padding particle to itself.
  const auto padding = static_cast<std::uint32_t>(n);
  std::vector<std::uint32_t> ids;
  std::vector<std::size_t> kept;
  for (std::size_t s = 0; s < settings.springs.size(); ++s) {
    const Spring& sp = settings.springs[s];
    if (!(sp.stiffness > 0)) continue;
    if (settings.fixed[sp.i] && settings.fixed[sp.j]) continue;
    ids.push_back(sp.i);
    ids.push_back(sp.j);
    kept.push_back(s);
  }
  std::size_t colours = 0;
  const std::vector<std::uint32_t> colour = colour_items(ids, 2, n, colours);
  slot_of_spring_.assign(settings.springs.size(), std::numeric_limits<std::uint32_t>::max());
  std::vector<std::size_t> order(kept.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return colour[a] != colour[b] ? colour[a] < colour[b] : ids[2 * a] < ids[2 * b];
  });
  spring_colour_start_.assign(1, 0);
  for (std::size_t k = 0, c = 0; c < colours; ++c) {
    for (; k < order.size() && colour[order[k]] == c; ++k) {
      const Spring& sp = settings.springs[kept[order[k]]];
      slot_of_spring_[kept[order[k]]] = static_cast<std::uint32_t>(spring_i_.size());
      spring_i_.push_back(sp.i);
      spring_j_.push_back(sp.j);
      spring_rest_.push_back(static_cast<float>(sp.rest_length));
      spring_compliance_.push_back(static_cast<float>(1.0 / sp.stiffness));
      spring_damping_.push_back(static_cast<float>(sp.damping));
    }
    while (spring_i_.size() % 8 != 0) {
      spring_i_.push_back(padding);
      spring_j_.push_back(padding);
      spring_rest_.push_back(1.f);
      spring_compliance_.push_back(1.f);
      spring_damping_.push_back(0.f);
    }
    spring_colour_start_.push_back(spring_i_.size());
  }

  // Triangles of the area term, coloured and padded the same way.
  triangle_colour_start_.assign(1, 0);
  if (settings.k_area > 0 && settings.mean_rest_area > 0) {
    area_compliance_ = static_cast<float>(settings.mean_rest_area / settings.k_area);
    std::vector<std::uint32_t> tids;
    for (const Triangle& t : settings.triangles) tids.insert(tids.end(), t.begin(), t.end());
    std::size_t tc = 0;
    const std::vector<std::uint32_t> tcol = colour_items(tids, 3, n, tc);
    std::vector<std::size_t> torder(settings.triangles.size());
    for (std::size_t k = 0; k < torder.size(); ++k) torder[k] = k;
    std::stable_sort(torder.begin(), torder.end(), [&](std::size_t a, std::size_t b) { return tcol[a] < tcol[b]; });
    for (std::size_t k = 0, c = 0; c < tc; ++c) {
      for (; k < torder.size() && tcol[torder[k]] == c; ++k) {
        const Triangle& t = settings.triangles[torder[k]];
        triangle_v0_.push_back(t[0]);
        triangle_v1_.push_back(t[1]);
        triangle_v2_.push_back(t[2]);
        triangle_rest_.push_back(static_cast<float>(settings.rest_areas[torder[k]]));
      }
      while (triangle_v0_.size() % 8 != 0) {
        triangle_v0_.push_back(padding);
        triangle_v1_.push_back(padding);
        triangle_v2_.push_back(padding);
        triangle_rest_.push_back(0.f);
      }
      triangle_colour_start_.push_back(triangle_v0_.size());
    }
  }
  if (settings.closed && settings.k_volume > 0 && settings.rest_volume > 0) {
    volume_compliance_ = settings.rest_volume / settings.k_volume;
    volume_gradient_.assign(3 * n, 0.f);
  }
  if (settings.k_home > 0) home_compliance_ = static_cast<float>(1.0 / settings.k_home);
  avx2_ = cpu_has_avx2_fma();
}

void XpbdSolver::set_simd(bool on) { avx2_ = on && cpu_has_avx2_fma(); }

void XpbdSolver::springs_changed(std::span<const std::uint32_t> springs) {
  for (const std::uint32_t s : springs) {
    if (s >= slot_of_spring_.size() || slot_of_spring_[s] == std::numeric_limits<std::uint32_t>::max()) continue;
    const Spring& sp = settings_.springs[s];
    const std::uint32_t slot = slot_of_spring_[s];
    spring_rest_[slot] = static_cast<float>(sp.rest_length);
    spring_compliance_[slot] = static_cast<float>(1.0 / sp.stiffness);
    spring_damping_[slot] = static_cast<float>(sp.damping);
  }
}

XpbdStats XpbdSolver::step(MassSpringState& state, const TissueLoads& loads, Real dt, XpbdContacts* contacts) {
  begin(state, loads, dt, contacts, options_.substeps);
  for (int s = 0; s < run_.substeps; ++s) {
    substep_constraints(s);
    substep_contacts(s);
    substep_velocities();
  }
  return finish(state);
}

void XpbdSolver::begin(MassSpringState& state, const TissueLoads& loads, Real dt, XpbdContacts* contacts,
                       int substeps) {
  const std::size_t n = x_.size() - 1;  // the padding particle stays at the origin, w = 0
  for (std::size_t k = 0; k < fixed_.size(); ++k) fixed_positions_[k] = state.positions[fixed_[k]];
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = state.positions[i];
    const Vec3& v = state.velocities[i];
    x_[i] = {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()), inverse_masses_[i]};
    v_[i] = {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()), 0.f};
  }
  substeps = std::max(substeps, 1);
  if (!primed_) {
    // The last substep's start, as far as the state tells it: x − v h. (The rest shape would make
    // a deformed tissue look as if it had jumped there: the contacts' reach, which follows the
    // last substep's motion, would open to its widest for the first step.)
    primed_ = true;
    const float h0 = static_cast<float>(dt / substeps);
    for (std::size_t i = 0; i < n; ++i)
      previous_[i] = {x_[i].x - h0 * v_[i].x, x_[i].y - h0 * v_[i].y, x_[i].z - h0 * v_[i].z, 0.f};
  }
  run_ = Run{};
  run_.loads = &loads;
  run_.contacts = contacts;
  run_.dt = dt;
  run_.substeps = substeps;
  run_.h = static_cast<float>(dt / substeps);
  run_.inv_h = 1.f / run_.h;
  run_.damp = static_cast<float>(1.0 / (1.0 + dt / substeps * settings_.damping));
  if (contacts != nullptr) contacts->begin_step(view(), substeps);
}

XpbdView XpbdSolver::view() {
  const std::size_t n = x_.size() - 1;
  return XpbdView{std::span(x_).first(n), std::span(previous_).first(n), settings_.masses, settings_.triangles};
}

void XpbdSolver::substep_constraints(int s) {
  const std::size_t n = x_.size() - 1;
  const float h = run_.h;
  const float inv_h = run_.inv_h;
  const float inv_h2 = inv_h * inv_h;
  const float damp = run_.damp;
  const float gx = static_cast<float>(settings_.gravity.x()) * h;
  const float gy = static_cast<float>(settings_.gravity.y()) * h;
  const float gz = static_cast<float>(settings_.gravity.z()) * h;
  const std::span<const Vec3> forces = run_.loads->forces();
  // Predict: external forces only at the vertices loads touched.
  if (!forces.empty())
    for (const std::uint32_t v : run_.loads->loaded_vertices()) {
      const float hw = h * x_[v].w;
      v_[v].x += hw * static_cast<float>(forces[v].x());
      v_[v].y += hw * static_cast<float>(forces[v].y());
      v_[v].z += hw * static_cast<float>(forces[v].z());
    }
  for (std::size_t i = 0; i < n; ++i) {
    XpbdParticle& p = x_[i];
    previous_[i] = p;
    if (p.w == 0.f) continue;
    XpbdParticle& u = v_[i];
    u.x = (u.x + gx) * damp;
    u.y = (u.y + gy) * damp;
    u.z = (u.z + gz) * damp;
    p.x += h * u.x;
    p.y += h * u.y;
    p.z += h * u.z;
  }
  const bool last = s + 1 == run_.substeps;
  solve_springs(inv_h2, last);
  if (area_compliance_ > 0) solve_triangles(inv_h2);
  // The volume term once per step, on the last substep, with α̃ = α/(h·dt): one global
  // constraint whose pass costs as much as the springs', and soft at the step's rate; α/(h·dt)
  // gives its correction the impulse of a whole step (Δv = Δx/h = dt·F/m).
  if (volume_compliance_ > 0 && last) solve_volume(inv_h / static_cast<float>(run_.dt));
  if (home_compliance_ > 0) solve_home(inv_h2);
  run_.substep = s;
}

void XpbdSolver::substep_contacts(int s) {
  if (run_.contacts != nullptr) run_.contacts->solve(view(), s, run_.substeps, run_.h);
}

void XpbdSolver::substep_velocities() {
  const std::size_t n = x_.size() - 1;
  const float inv_h = run_.inv_h;
  for (std::size_t i = 0; i < n; ++i) {
    v_[i].x = (x_[i].x - previous_[i].x) * inv_h;
    v_[i].y = (x_[i].y - previous_[i].y) * inv_h;
    v_[i].z = (x_[i].z - previous_[i].z) * inv_h;
  }
  if (run_.contacts != nullptr) run_.contacts->solve_velocities(std::span(v_).first(n));
}

XpbdStats XpbdSolver::finish(MassSpringState& state) {
  const std::size_t n = x_.size() - 1;
  damp_springs(static_cast<float>(run_.dt));

  XpbdStats stats;
  stats.max_strain = max_strain_;
  bool finite = true;
  for (std::size_t i = 0; i < n; ++i) {
    state.positions[i] = Vec3(x_[i].x, x_[i].y, x_[i].z);
    state.velocities[i] = Vec3(v_[i].x, v_[i].y, v_[i].z);
    finite = finite && std::isfinite(x_[i].x + x_[i].y + x_[i].z + v_[i].x + v_[i].y + v_[i].z);
  }
  for (std::size_t k = 0; k < fixed_.size(); ++k) {
    state.positions[fixed_[k]] = fixed_positions_[k];
    state.velocities[fixed_[k]] = Vec3::Zero();
  }
  if (!finite) stats.max_strain = std::numeric_limits<Real>::quiet_NaN();
  return stats;
}

tissue_detail::XpbdSpringColour XpbdSolver::spring_colour(std::size_t c) const {
  const std::size_t begin = spring_colour_start_[c];
  return {spring_i_.data() + begin,         spring_j_.data() + begin,      spring_rest_.data() + begin,
          spring_compliance_.data() + begin, spring_damping_.data() + begin, spring_colour_start_[c + 1] - begin};
}

void XpbdSolver::damp_springs(float h) {
  for (std::size_t c = 0; c + 1 < spring_colour_start_.size(); ++c) {
    if (avx2_)
      tissue_detail::xpbd_dashpots_avx2(x_.data(), v_.data(), spring_colour(c), h);
    else
      tissue_detail::xpbd_dashpots_scalar(x_.data(), v_.data(), spring_colour(c), h);
  }
}

void XpbdSolver::solve_springs(float inv_h2, bool last) {
  float worst = 0;
  for (std::size_t c = 0; c + 1 < spring_colour_start_.size(); ++c) {
    const tissue_detail::XpbdSpringColour colour = spring_colour(c);
    const float w = avx2_ ? tissue_detail::xpbd_springs_avx2(x_.data(), colour, inv_h2, last)
                          : tissue_detail::xpbd_springs_scalar(x_.data(), colour, inv_h2, last);
    worst = std::max(worst, w);
  }
  if (last) max_strain_ = worst;
}

void XpbdSolver::solve_triangles(float inv_h2) {
  const float alpha = area_compliance_ * inv_h2;
  for (std::size_t c = 0; c + 1 < triangle_colour_start_.size(); ++c) {
    const std::size_t begin = triangle_colour_start_[c];
    const tissue_detail::XpbdTriangleColour colour{triangle_v0_.data() + begin, triangle_v1_.data() + begin,
                                                   triangle_v2_.data() + begin, triangle_rest_.data() + begin,
                                                   triangle_colour_start_[c + 1] - begin};
    if (avx2_)
      tissue_detail::xpbd_triangles_avx2(x_.data(), colour, alpha);
    else
      tissue_detail::xpbd_triangles_scalar(x_.data(), colour, alpha);
  }
}

void XpbdSolver::solve_volume(float inv_h_dt) {
  // ∂(6V)/∂x_a = x_b × x_c (and cyclically), summed per vertex in float; V itself in double.
  std::fill(volume_gradient_.begin(), volume_gradient_.end(), 0.f);
  double six_volume = 0;
  float* g = volume_gradient_.data();
  for (const Triangle& t : settings_.triangles) {
    const XpbdParticle& a = x_[t[0]];
    const XpbdParticle& b = x_[t[1]];
    const XpbdParticle& c = x_[t[2]];
    const float bc[3] = {b.y * c.z - b.z * c.y, b.z * c.x - b.x * c.z, b.x * c.y - b.y * c.x};
    const float ca[3] = {c.y * a.z - c.z * a.y, c.z * a.x - c.x * a.z, c.x * a.y - c.y * a.x};
    const float ab[3] = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    six_volume += static_cast<double>(a.x * bc[0] + a.y * bc[1] + a.z * bc[2]);
    for (int k = 0; k < 3; ++k) {
      g[3 * t[0] + k] += bc[k];
      g[3 * t[1] + k] += ca[k];
      g[3 * t[2] + k] += ab[k];
    }
  }
  const std::size_t n = x_.size() - 1;
  double weighted = 0;
  for (std::size_t i = 0; i < n; ++i)
    weighted += x_[i].w * (g[3 * i] * g[3 * i] + g[3 * i + 1] * g[3 * i + 1] + g[3 * i + 2] * g[3 * i + 2]);
  // C = V − V0 with ∇V = g/6: Δλ = −C / (Σ w |g|²/36 + α̃), Δx_i = w_i (g_i/6) Δλ.
  const double denominator = weighted / 36 + volume_compliance_ * inv_h_dt;
  if (!(denominator > 0)) return;
  const auto scale = static_cast<float>(-(six_volume / 6 - settings_.rest_volume) / denominator / 6);
  for (std::size_t i = 0; i < n; ++i) {
    const float s = x_[i].w * scale;
    x_[i].x += g[3 * i] * s;
    x_[i].y += g[3 * i + 1] * s;
    x_[i].z += g[3 * i + 2] * s;
  }
}

void XpbdSolver::solve_home(float inv_h2) {
  const float alpha = home_compliance_ * inv_h2;
  for (std::size_t i = 0; i + 1 < x_.size(); ++i) {
    XpbdParticle& p = x_[i];
    if (p.w == 0.f) continue;
    const Vec3& r = settings_.home_positions[i];
    const float f = p.w / (p.w + alpha);  // the vector constraint x − x0 solved exactly
    p.x -= f * (p.x - static_cast<float>(r.x()));
    p.y -= f * (p.y - static_cast<float>(r.y()));
    p.z -= f * (p.z - static_cast<float>(r.z()));
  }
}

}  // namespace trocar

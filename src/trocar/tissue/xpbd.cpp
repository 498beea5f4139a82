// XPBD with substeps (xpbd.h). The passes are scalar Gauss–Seidel over float particles in
// colour order; the colouring is what lets a pass vectorise or run on a GPU later.
#include "trocar/tissue/xpbd.h"

#include <algorithm>
#include <cmath>

#include "trocar/core/error.h"

namespace trocar {
namespace {

struct F3 {
  float x, y, z;
};
inline F3 sub(const XpbdParticle& a, const XpbdParticle& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline F3 cross(const F3& a, const F3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float dot(const F3& a, const F3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline void add_scaled(XpbdParticle& p, const F3& d, float s) {
  p.x += d.x * s;
  p.y += d.y * s;
  p.z += d.z * s;
}

}  // namespace

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
  x_.resize(n);
  previous_.resize(n);
  vx_.assign(n, 0.f);
  vy_.assign(n, 0.f);
  vz_.assign(n, 0.f);
  inverse_masses_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& r = settings.rest_positions[i];
    previous_[i] = {static_cast<float>(r.x()), static_cast<float>(r.y()), static_cast<float>(r.z()), 0.f};
    inverse_masses_[i] = settings.fixed[i] ? 0.f : static_cast<float>(settings.inverse_masses[i]);
    if (settings.fixed[i]) fixed_.push_back(static_cast<std::uint32_t>(i));
  }
  fixed_positions_.resize(fixed_.size());

  // Springs with a stiffness, coloured, each colour sorted by its first vertex (memory order).
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
  std::vector<std::uint32_t> colour = colour_items(ids, 2, n, colours);
  std::vector<std::size_t> order(kept.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return colour[a] != colour[b] ? colour[a] < colour[b] : ids[2 * a] < ids[2 * b];
  });
  spring_colour_start_.assign(colours + 1, 0);
  for (const std::size_t k : order) {
    const Spring& sp = settings.springs[kept[k]];
    springs_.push_back({sp.i, sp.j, static_cast<float>(sp.rest_length), static_cast<float>(1.0 / sp.stiffness)});
    spring_damping_.push_back(static_cast<float>(sp.damping));
    ++spring_colour_start_[colour[k] + 1];
  }
  for (std::size_t c = 0; c < colours; ++c) spring_colour_start_[c + 1] += spring_colour_start_[c];

  // Triangles of the area term, coloured the same way.
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
    triangle_colour_start_.assign(tc + 1, 0);
    for (const std::size_t k : torder) {
      const Triangle& t = settings.triangles[k];
      triangles_.push_back({{t[0], t[1], t[2]}, static_cast<float>(settings.rest_areas[k])});
      ++triangle_colour_start_[tcol[k] + 1];
    }
    for (std::size_t c = 0; c < tc; ++c) triangle_colour_start_[c + 1] += triangle_colour_start_[c];
  }
  if (settings.closed && settings.k_volume > 0 && settings.rest_volume > 0) {
    volume_compliance_ = settings.rest_volume / settings.k_volume;
    volume_gradient_.assign(n, Vec3::Zero());
  }
  if (settings.k_home > 0) home_compliance_ = static_cast<float>(1.0 / settings.k_home);
}

XpbdStats XpbdSolver::step(MassSpringState& state, const TissueLoads& loads, Real dt, XpbdContacts* contacts) {
  const std::size_t n = x_.size();
  for (std::size_t k = 0; k < fixed_.size(); ++k) fixed_positions_[k] = state.positions[fixed_[k]];
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = state.positions[i];
    const Vec3& v = state.velocities[i];
    x_[i] = {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()), inverse_masses_[i]};
    vx_[i] = static_cast<float>(v.x());
    vy_[i] = static_cast<float>(v.y());
    vz_[i] = static_cast<float>(v.z());
  }
  const XpbdView view{x_, previous_, settings_.masses, settings_.triangles};
  const int substeps = options_.substeps;
  if (contacts != nullptr) contacts->begin_step(view, dt, substeps);

  const float h = static_cast<float>(dt / substeps);
  const float inv_h = 1.f / h;
  const float inv_h2 = inv_h * inv_h;
  const float damp = static_cast<float>(1.0 / (1.0 + dt / substeps * settings_.damping));
  const float gx = static_cast<float>(settings_.gravity.x()) * h;
  const float gy = static_cast<float>(settings_.gravity.y()) * h;
  const float gz = static_cast<float>(settings_.gravity.z()) * h;
  const std::span<const Vec3> forces = loads.forces();
  for (int s = 0; s < substeps; ++s) {
    // Predict: external forces only at the vertices loads touched.
    if (!forces.empty())
      for (const std::uint32_t v : loads.loaded_vertices()) {
        const float hw = h * x_[v].w;
        vx_[v] += hw * static_cast<float>(forces[v].x());
        vy_[v] += hw * static_cast<float>(forces[v].y());
        vz_[v] += hw * static_cast<float>(forces[v].z());
      }
    for (std::size_t i = 0; i < n; ++i) {
      XpbdParticle& p = x_[i];
      previous_[i] = p;
      if (p.w == 0.f) continue;
      vx_[i] = (vx_[i] + gx) * damp;
      vy_[i] = (vy_[i] + gy) * damp;
      vz_[i] = (vz_[i] + gz) * damp;
      p.x += h * vx_[i];
      p.y += h * vy_[i];
      p.z += h * vz_[i];
    }
    solve_springs(h, inv_h2, s + 1 == substeps);
    if (area_compliance_ > 0) solve_triangles(inv_h2);
    if (volume_compliance_ > 0) solve_volume(inv_h2);
    if (home_compliance_ > 0) solve_home(inv_h2);
    if (contacts != nullptr) contacts->solve(view, s, substeps, h);
    for (std::size_t i = 0; i < n; ++i) {
      vx_[i] = (x_[i].x - previous_[i].x) * inv_h;
      vy_[i] = (x_[i].y - previous_[i].y) * inv_h;
      vz_[i] = (x_[i].z - previous_[i].z) * inv_h;
    }
    if (contacts != nullptr) contacts->solve_velocities(vx_, vy_, vz_);
  }

  XpbdStats stats;
  stats.max_strain = max_strain_;
  bool finite = true;
  for (std::size_t i = 0; i < n; ++i) {
    state.positions[i] = Vec3(x_[i].x, x_[i].y, x_[i].z);
    state.velocities[i] = Vec3(vx_[i], vy_[i], vz_[i]);
    finite = finite && std::isfinite(x_[i].x + x_[i].y + x_[i].z + vx_[i] + vy_[i] + vz_[i]);
  }
  for (std::size_t k = 0; k < fixed_.size(); ++k) {
    state.positions[fixed_[k]] = fixed_positions_[k];
    state.velocities[fixed_[k]] = Vec3::Zero();
  }
  if (volume_compliance_ > 0) {
    Real volume = 0;
    for (const Triangle& t : settings_.triangles)
      volume += state.positions[t[0]].dot(state.positions[t[1]].cross(state.positions[t[2]]));
    stats.volume_error = std::abs(volume / 6 - settings_.rest_volume) / settings_.rest_volume;
  }
  if (!finite) stats.max_strain = std::numeric_limits<Real>::quiet_NaN();
  return stats;
}

void XpbdSolver::solve_springs(float h, float inv_h2, bool last) {
  float worst = 0;
  const float inv_h = 1.f / h;
  for (std::size_t k = 0; k < springs_.size(); ++k) {
    const SpringConstraint& c = springs_[k];
    XpbdParticle& a = x_[c.i];
    XpbdParticle& b = x_[c.j];
    const float w = a.w + b.w;
    if (w == 0.f) continue;
    const F3 d = sub(a, b);
    const float length = std::sqrt(dot(d, d));
    if (!(length > 1e-12f)) continue;
    const float inv_length = 1.f / length;
    const F3 u{d.x * inv_length, d.y * inv_length, d.z * inv_length};
    const float constraint = length - c.rest;
    const float alpha = c.compliance * inv_h2;
    // XPBD eq. 26: γ = α̃ β̃ / h = α λ / h; the relative motion this substep along u.
    const float gamma = c.compliance * spring_damping_[k] * inv_h;
    const XpbdParticle& pa = previous_[c.i];
    const XpbdParticle& pb = previous_[c.j];
    const F3 motion{(a.x - pa.x) - (b.x - pb.x), (a.y - pa.y) - (b.y - pb.y), (a.z - pa.z) - (b.z - pb.z)};
    const float dlambda = (-constraint - gamma * dot(u, motion)) / ((1.f + gamma) * w + alpha);
    add_scaled(a, u, a.w * dlambda);
    add_scaled(b, u, -b.w * dlambda);
    if (last) worst = std::max(worst, std::abs(constraint) / c.rest);
  }
  if (last) max_strain_ = worst;
}

void XpbdSolver::solve_triangles(float inv_h2) {
  const float alpha = area_compliance_ * inv_h2;
  for (const TriangleConstraint& t : triangles_) {
    XpbdParticle& p0 = x_[t.v[0]];
    XpbdParticle& p1 = x_[t.v[1]];
    XpbdParticle& p2 = x_[t.v[2]];
    const F3 normal = cross(sub(p1, p0), sub(p2, p0));
    const float twice_area = std::sqrt(dot(normal, normal));
    if (!(twice_area > 1e-20f)) continue;
    const float s = 0.5f / twice_area;  // ∂A/∂x_a = ½ n̂ × (x_c − x_b), (a, b, c) cyclic
    const F3 g0 = cross(normal, sub(p2, p1));
    const F3 g1 = cross(normal, sub(p0, p2));
    const F3 g2 = cross(normal, sub(p1, p0));
    const float denominator =
        s * s * (p0.w * dot(g0, g0) + p1.w * dot(g1, g1) + p2.w * dot(g2, g2)) + alpha;
    if (!(denominator > 0.f)) continue;
    const float dlambda = -(0.5f * twice_area - t.rest_area) / denominator * s;
    add_scaled(p0, g0, p0.w * dlambda);
    add_scaled(p1, g1, p1.w * dlambda);
    add_scaled(p2, g2, p2.w * dlambda);
  }
}

void XpbdSolver::solve_volume(float inv_h2) {
  std::fill(volume_gradient_.begin(), volume_gradient_.end(), Vec3::Zero());
  double volume = 0;
  for (const Triangle& t : settings_.triangles) {
    const Vec3 a(x_[t[0]].x, x_[t[0]].y, x_[t[0]].z);
    const Vec3 b(x_[t[1]].x, x_[t[1]].y, x_[t[1]].z);
    const Vec3 c(x_[t[2]].x, x_[t[2]].y, x_[t[2]].z);
    const Vec3 bc = b.cross(c);
    volume += a.dot(bc);
    volume_gradient_[t[0]] += bc;  // ∂(a·(b×c))/∂a = b×c, and cyclically
    volume_gradient_[t[1]] += c.cross(a);
    volume_gradient_[t[2]] += a.cross(b);
  }
  volume /= 6;
  double denominator = volume_compliance_ * inv_h2;
  for (std::size_t i = 0; i < x_.size(); ++i)
    denominator += x_[i].w * volume_gradient_[i].squaredNorm() / 36;
  if (!(denominator > 0)) return;
  const double dlambda = -(volume - settings_.rest_volume) / denominator / 6;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    if (x_[i].w == 0.f) continue;
    const Vec3 d = volume_gradient_[i] * (dlambda * x_[i].w);
    x_[i].x += static_cast<float>(d.x());
    x_[i].y += static_cast<float>(d.y());
    x_[i].z += static_cast<float>(d.z());
  }
}

void XpbdSolver::solve_home(float inv_h2) {
  const float alpha = home_compliance_ * inv_h2;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    XpbdParticle& p = x_[i];
    if (p.w == 0.f) continue;
    const Vec3& r = settings_.rest_positions[i];
    const float f = p.w / (p.w + alpha);  // the vector constraint x − x0 solved exactly
    p.x -= f * (p.x - static_cast<float>(r.x()));
    p.y -= f * (p.y - static_cast<float>(r.y()));
    p.z -= f * (p.z - static_cast<float>(r.z()));
  }
}

}  // namespace trocar

#include "trocar/response/solver_contact.h"

#include "trocar/geometry/closest_point.h"

#include <algorithm>
#include <cmath>

namespace trocar {
namespace {

Vec3 position(const XpbdParticle& p) { return Vec3(p.x, p.y, p.z); }
void store(XpbdParticle& p, const Vec3& x) {
  p.x = static_cast<float>(x.x());
  p.y = static_cast<float>(x.y());
  p.z = static_cast<float>(x.z());
}
/// R⁻¹(x − t): a world point in the pose's frame.
Vec3 to_local(const Pose& pose, const Vec3& x) { return pose.rotation.conjugate() * (x - pose.translation); }

/// A sample under a face counts when its projection lies inside the face to this tolerance (of
/// the barycentric coordinates): an edge shared by two faces is covered by both.
constexpr Real kInsideFace = 0.01;

}  // namespace

Pose interpolate_pose(const Pose& a, const Pose& b, Real f) {
  Pose p;
  p.rotation = a.rotation.slerp(f, b.rotation);
  p.translation = a.translation + f * (b.translation - a.translation);
  return p;
}

void InstrumentContacts::reset(std::span<const Vec3> positions, std::span<const Triangle> triangles, bool closed,
                               std::span<const SolverInstrument> instruments, const ResponseSettings& settings) {
  settings_ = settings;
  per_.clear();
  per_.resize(instruments.size());
  for (std::size_t i = 0; i < instruments.size(); ++i) {
    PerInstrument& p = per_[i];
    p.in = instruments[i];
    const std::size_t samples = p.in.field != nullptr ? p.in.field->samples().size() : 0;
    p.samples.reserve(samples);
    p.sample_world.reserve(samples);
    p.pairs.reserve(kMaxPairs);
    p.points.reserve(kMaxPoints);
    p.hits.assign(p.in.instrument != nullptr ? p.in.instrument->world_positions().size() : 0, 0);
    build_sample_grid(p);
  }
  set_surface(positions, triangles, closed);
}

void InstrumentContacts::set_surface(std::span<const Vec3> positions, std::span<const Triangle> triangles, bool closed) {
  const std::size_t vertex_count = positions.size();
  triangles_ = triangles;
  closed_ = closed;
  vertex_first_.assign(vertex_count + 1, 0);
  for (const Triangle& t : triangles)
    for (const std::uint32_t v : t) ++vertex_first_[v + 1];
  for (std::size_t v = 0; v < vertex_count; ++v) vertex_first_[v + 1] += vertex_first_[v];
  vertex_faces_.resize(vertex_first_.back());
  std::vector<std::uint32_t> fill(vertex_first_.begin(), vertex_first_.end() - 1);
  for (std::size_t k = 0; k < triangles.size(); ++k)
    for (const std::uint32_t v : triangles[k]) vertex_faces_[fill[v]++] = static_cast<std::uint32_t>(k);
  triangle_stamp_.assign(triangles.size(), 0);
  longest_edge_ = 0;
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k)
      longest_edge_ = std::max(longest_edge_, (positions[t[k]] - positions[t[(k + 1) % 3]]).norm());
  is_held_.assign(vertex_count, 0);
  touched_stamp_.assign(vertex_count, 0);
  moved_.reserve(4 * vertex_count);
  for (PerInstrument& p : per_) {
    p.candidates.clear();
    p.near.clear();
    p.candidates.reserve(vertex_count);
    p.near.reserve(vertex_count);
    p.hint.assign(vertex_count, MeshDistance::kNoTriangle);
    p.held.clear();
    p.held.reserve(vertex_count);
  }
}

void InstrumentContacts::remodel(std::span<const Vec3> positions, std::span<const Triangle> triangles, bool closed,
                                 std::span<const std::uint32_t> vertex_origin) {
  // The instruments' sides (their sample grids) stay; only the tissue's is rebuilt.
  std::vector<std::vector<HeldVertex>> held;
  for (const PerInstrument& p : per_) held.push_back(p.held);
  const std::size_t old_count = is_held_.size();
  set_surface(positions, triangles, closed);
  std::vector<std::int64_t> slot(old_count, -1);
  for (std::size_t i = 0; i < per_.size(); ++i) {
    for (std::size_t k = 0; k < held[i].size(); ++k) slot[held[i][k].vertex] = static_cast<std::int64_t>(k);
    for (std::uint32_t v = 0; v < vertex_origin.size(); ++v) {
      const std::uint32_t old = vertex_origin[v];
      if (old >= old_count || slot[old] < 0) continue;
      per_[i].held.push_back({v, held[i][static_cast<std::size_t>(slot[old])].local});
      is_held_[v] = 1;
    }
    for (const HeldVertex& h : held[i]) slot[h.vertex] = -1;
  }
}

void InstrumentContacts::build_sample_grid(PerInstrument& p) {
  p.grid_start.clear();
  if (p.in.field == nullptr || p.in.field->empty()) return;
  const std::span<const Vec3> samples = p.in.field->samples();
  p.sample_stamp.assign(samples.size(), 0);
  p.sample_index.assign(samples.size(), 0);
  p.sample_from.assign(samples.size(), Vec3::Zero());
  p.sample_to.assign(samples.size(), Vec3::Zero());
  p.sample_placed.assign(samples.size(), 0);
  p.grid_box = Aabb::of_points(samples).inflated(1e-6);
  p.sample_radius = 0;
  for (const Vec3& q : samples) p.sample_radius = std::max(p.sample_radius, q.norm());
  const Vec3 size = p.grid_box.size();
  // 2 mm cells, coarser when that would exceed 2^18 cells.
  p.grid_cell = std::max(Real{0.002}, std::cbrt(size.prod() / (1 << 18)));
  std::size_t cells = 1;
  for (int a = 0; a < 3; ++a) {
    p.grid_n[a] = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(size[a] / p.grid_cell)));
    cells *= p.grid_n[a];
  }
  const auto cell_of = [&](const Vec3& q) {
    std::size_t c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = std::min(static_cast<std::size_t>(std::max(Real{0}, (q[a] - p.grid_box.min[a]) / p.grid_cell)),
                      p.grid_n[a] - 1);
    return (c[2] * p.grid_n[1] + c[1]) * p.grid_n[0] + c[0];
  };
  p.grid_start.assign(cells + 1, 0);
  for (const Vec3& q : samples) ++p.grid_start[cell_of(q) + 1];
  for (std::size_t c = 0; c < cells; ++c) p.grid_start[c + 1] += p.grid_start[c];
  p.grid_samples.resize(samples.size());
  std::vector<std::uint32_t> fill(p.grid_start.begin(), p.grid_start.end() - 1);
  for (std::size_t k = 0; k < samples.size(); ++k) p.grid_samples[fill[cell_of(samples[k])]++] = static_cast<std::uint32_t>(k);
}

void InstrumentContacts::begin_step(const XpbdView& view, int substeps) {
  substeps_ = substeps;
  contacts_ = 0;
  ++stamp_;
  // How far a tissue vertex may move this step: twice its last step's motion (the previous
  // substep's displacement × substeps), at least 0.2 mm.
  Real fastest = 0;
  for (std::size_t v = 0; v < view.x.size(); ++v) {
    const XpbdParticle& a = view.x[v];
    const XpbdParticle& b = view.previous[v];
    const float dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
    fastest = std::max(fastest, static_cast<Real>(dx * dx + dy * dy + dz * dz));
  }
  tissue_reach_ = std::clamp(2 * std::sqrt(fastest) * substeps, Real{2e-4}, kReach);
  for (PerInstrument& p : per_) {
    p.force.setZero();
    p.torque.setZero();
    std::fill(p.hits.begin(), p.hits.end(), std::uint8_t{0});
    if (p.in.instrument == nullptr || p.in.field == nullptr || p.in.field->empty()) continue;
    p.from = p.in.instrument->previous_pose();
    p.to = p.in.instrument->pose();
    p.depth_limit = p.in.thickness + (p.to.translation - p.from.translation).norm() + settings_.contact_margin;
    p.port_limit = std::max(p.in.instrument->port_height(p.from), p.in.instrument->port_height(p.to));
    find_candidates(p, view);
    update_grasp(p, view);
    find_pairs(p, view);
  }
}

void InstrumentContacts::find_candidates(PerInstrument& p, const XpbdView& view) {
  const Obb& local = p.in.instrument->local_obb();
  Aabb box = p.from.apply(local).bounds();
  box.expand(p.to.apply(local).bounds());
  box = box.inflated(kReach + settings_.contact_margin);
  p.box = box;
  // A face can reach the box with every vertex outside it (a coarse mesh under a thin wire):
  // vertices within the longest edge of the box are the corners of every face that can.
  const Aabb wide = box.inflated(longest_edge_);
  const auto inside = [](const XpbdParticle& x, const Aabb& b) {
    return x.x >= b.min.x() && x.x <= b.max.x() && x.y >= b.min.y() && x.y <= b.max.y() && x.z >= b.min.z() &&
           x.z <= b.max.z();
  };
  // The axis-aligned box of a long shaft lying obliquely over a sheet holds most of the sheet;
  // the instrument's own boxes at both poses, grown by the same margins plus the step's sweep
  // (translation, and the rotation's arc at the box's far corner), hold only what it can reach.
  const Obb from = p.from.apply(local), to = p.to.apply(local);
  const Real angle = p.from.rotation.angularDistance(p.to.rotation);
  const Real sweep = (p.to.translation - p.from.translation).norm() + angle * (local.center.norm() + local.half_extents.norm());
  const Real grow = kReach + settings_.contact_margin + sweep;
  const auto near_obb = [&](const XpbdParticle& x, Real g) {
    const Vec3 q(x.x, x.y, x.z);
    return from.contains(q, g) || to.contains(q, g);
  };
  p.candidates.clear();
  p.near.clear();
  for (std::size_t v = 0; v < view.x.size(); ++v) {
    const XpbdParticle& x = view.x[v];
    if (!inside(x, wide) || !near_obb(x, grow + longest_edge_)) continue;
    p.near.push_back(static_cast<std::uint32_t>(v));
    if (x.w == 0.f || is_held_[v] != 0 || !inside(x, box) || !near_obb(x, grow)) continue;
    p.candidates.push_back(static_cast<std::uint32_t>(v));
  }
}

void InstrumentContacts::update_grasp(PerInstrument& p, const XpbdView& view) {
  const Instrument& instrument = *p.in.instrument;
  const bool closed = instrument.has_jaws() && instrument.jaw() >= settings_.grasp_closure;
  if (!closed) {
    for (const HeldVertex& h : p.held) is_held_[h.vertex] = 0;
    p.held.clear();
    return;
  }
  for (const std::uint32_t v : p.candidates) {
    if (is_held_[v] != 0) continue;
    const Vec3 q = to_local(p.from, position(view.x[v]));
    if (p.in.field->lower_bound(q) > kGrabDistance) continue;
    const SignedDistanceResult r = p.in.field->query(q, p.hint[v]);
    if (r.distance > kGrabDistance || !instrument.is_jaw_triangle(r.triangle)) continue;
    p.held.push_back({v, q});
    is_held_[v] = 1;
  }
}

void InstrumentContacts::find_pairs(PerInstrument& p, const XpbdView& view) {
  p.samples.clear();
  p.pairs.clear();
  if (p.near.empty() || p.grid_start.empty()) return;
  ++p.sample_round;
  const std::span<const Vec3> samples = p.in.field->samples();
  const Pose from_inverse = p.from.inverse();
  // How far any sample moves over the step: the translation and the rotation's arc at the
  // farthest sample (|(R₁ − R₀)s| ≤ angle·|s|).
  const Real path = (p.to.translation - p.from.translation).norm() +
                    p.from.rotation.angularDistance(p.to.rotation) * p.sample_radius;
  // add_pair keeps a sample only if, at the step's start, it lies over the face within `lateral`
  // in the face's plane and at a height d₀ over it in [below, above]: below −kRecover for a closed
  // surface (either side of an open sheet: −above), above the margin and the reach plus the
  // sample's own path. The grid is searched over that thin prism's box only (the face's box grown
  // by the depth limit on every side held the shaft's whole cross-section).
  const Real above = settings_.contact_margin + tissue_reach_ + path;
  const Real below = closed_ ? -kRecover : -above;
  const Real lateral = above;
  // Triangles around the near vertices whose box meets the instrument's, each once; for each,
  // the samples in the grid cells under its prism (in the instrument's frame at the step's start).
  ++stamp_;
  for (const std::uint32_t v : p.near)
    for (std::uint32_t k = vertex_first_[v]; k < vertex_first_[v + 1]; ++k) {
      const std::uint32_t t = vertex_faces_[k];
      if (triangle_stamp_[t] == stamp_) continue;
      triangle_stamp_[t] = stamp_;
      const Triangle& tri = triangles_[t];
      const Vec3 x0 = position(view.x[tri[0]]), x1 = position(view.x[tri[1]]), x2 = position(view.x[tri[2]]);
      Aabb face;
      face.expand(x0);
      face.expand(x1);
      face.expand(x2);
      if (!face.overlaps(p.box)) continue;
      Vec3 n = (x1 - x0).cross(x2 - x0);
      const Real nn = n.norm();
      if (!(nn > 0)) continue;
      n /= nn;
      // The face's bounding sphere (centroid, farthest corner): add_pair's cheap test before the exact one.
      const Vec3 centre = (x0 + x1 + x2) / 3;
      const Real radius = std::sqrt(std::max({(x0 - centre).squaredNorm(), (x1 - centre).squaredNorm(),
                                              (x2 - centre).squaredNorm()}));
      const FaceSphere sphere{centre, radius};
      face = face.inflated(p.depth_limit + tissue_reach_);
      Aabb local;
      for (const Vec3* x : {&x0, &x1, &x2}) {
        local.expand(from_inverse.apply(Vec3(*x + below * n)));
        local.expand(from_inverse.apply(Vec3(*x + above * n)));
      }
      local = local.inflated(lateral + 1e-7);  // and a rounding's worth
      std::size_t lo[3], hi[3];
      bool empty = false;
      for (int a = 0; a < 3; ++a) {
        const Real l = (local.min[a] - p.grid_box.min[a]) / p.grid_cell;
        const Real h = (local.max[a] - p.grid_box.min[a]) / p.grid_cell;
        if (h < 0 || l >= static_cast<Real>(p.grid_n[a])) empty = true;
        lo[a] = static_cast<std::size_t>(std::max(l, Real{0}));
        hi[a] = std::min(static_cast<std::size_t>(std::max(h, Real{0})), p.grid_n[a] - 1);
      }
      if (empty) continue;
      for (std::size_t cz = lo[2]; cz <= hi[2]; ++cz)
        for (std::size_t cy = lo[1]; cy <= hi[1]; ++cy)
          for (std::size_t cx = lo[0]; cx <= hi[0]; ++cx) {
            const std::size_t cell = (cz * p.grid_n[1] + cy) * p.grid_n[0] + cx;
            for (std::uint32_t k2 = p.grid_start[cell]; k2 < p.grid_start[cell + 1]; ++k2)
              add_pair(p, p.grid_samples[k2], t, face, n, x0, x1, x2, sphere, samples);
          }
    }
}

void InstrumentContacts::add_pair(PerInstrument& p, std::uint32_t sample, std::uint32_t triangle, const Aabb& face,
                                  const Vec3& n, const Vec3& x0, const Vec3& x1, const Vec3& x2,
                                  const FaceSphere& sphere, std::span<const Vec3> samples) {
  // A sample meets many faces: placed in the world once a round.
  if (p.sample_placed[sample] != p.sample_round) {
    p.sample_placed[sample] = p.sample_round;
    p.sample_from[sample] = p.from.apply(samples[sample]);
    p.sample_to[sample] = p.to.apply(samples[sample]);
  }
  const Vec3& a0 = p.sample_from[sample];
  const Vec3& a1 = p.sample_to[sample];
  // The shaft beyond its port is outside the body (Instrument::set_port): a sample there at both
  // ends of the step pushes no face.
  if (p.in.instrument->local_shaft().dot(samples[sample]) > p.port_limit) return;
  Aabb path;
  path.expand(a0);
  path.expand(a1);
  if (!path.overlaps(face)) return;
  // The sample's height over the face's plane at both ends of its path: a pair can act only if,
  // with the face moving up to tissue_reach_, the sample comes within the margin above the face
  // or less than the depth limit below it.
  const Real d0 = n.dot(a0 - x0), d1 = n.dot(a1 - x0);
  const Real side = closed_ || d0 >= 0 ? 1 : -1;
  // A sample that starts the step deeper under the face than kRecover did not come from above
  // it this step (it is past the face, or the face is the organ's far side): pushing the face
  // through the instrument would tear the surface across it.
  if (side * d0 < -kRecover) return;
  const Real lo = std::min(side * d0, side * d1), hi = std::max(side * d0, side * d1);
  if (lo > settings_.contact_margin + tissue_reach_ || hi < -p.depth_limit - tissue_reach_) return;
  // And beside the face: the sample's path must come within the reach of the face itself, not
  // only of its plane (a face along a shaft would otherwise pair with every sample over it).
  const Real lateral = settings_.contact_margin + tissue_reach_ + (a1 - a0).norm();
  const Vec3 over = a0 - d0 * n;  // a0 in the face's plane: only the in-plane distance counts here
  // First against the sphere round the face, then exactly.
  const Real reach = sphere.radius + lateral;
  if ((over - sphere.centre).squaredNorm() > reach * reach) return;
  if ((closest_point_on_triangle(over, x0, x1, x2).point - over).squaredNorm() > lateral * lateral) return;
  if (p.pairs.size() == p.pairs.capacity()) return;  // the bound on a step's work: never grow, never hang
  if (p.sample_stamp[sample] != p.sample_round) {
    p.sample_stamp[sample] = p.sample_round;
    p.sample_index[sample] = static_cast<std::uint32_t>(p.samples.size());
    p.samples.push_back(sample);
  }
  p.pairs.push_back({p.sample_index[sample], triangle, static_cast<float>(side)});
}

void InstrumentContacts::solve(const XpbdView& view, int substep, int substeps, Real h) {
  const Real inv_h2 = 1 / (h * h);
  moved_.clear();
  for (PerInstrument& p : per_) {
    if (p.in.instrument == nullptr || p.in.field == nullptr || p.in.field->empty()) continue;
    p.points.clear();
    const Pose pose = interpolate_pose(p.from, p.to, static_cast<Real>(substep + 1) / substeps);
    const Pose before = interpolate_pose(p.from, p.to, static_cast<Real>(substep) / substeps);
    // Held vertices: an attachment of zero compliance, solved last; the tissue's pull on the
    // jaws is the correction it takes (−m Δx/h² per substep, as for a contact).
    for (const HeldVertex& held : p.held) {
      XpbdParticle& particle = view.x[held.vertex];
      const Vec3 x = position(particle), attached = pose.apply(held.local);
      store(particle, attached);
      const Vec3 impulse = (attached - x) * (view.masses[held.vertex] * inv_h2 / substeps_);
      p.force -= impulse;
      p.torque += (attached - p.to.translation).cross(-impulse);
    }
    if (!p.pairs.empty()) {
      const std::span<const Vec3> samples = p.in.field->samples();
      p.sample_world.resize(p.samples.size());
      for (std::size_t s = 0; s < p.samples.size(); ++s) p.sample_world[s] = pose.apply(samples[p.samples[s]]);
      push_faces(p, view, inv_h2);
    }
    project_vertices(p, view, pose, before, inv_h2);
  }
}

void InstrumentContacts::push_faces(PerInstrument& p, const XpbdView& view, Real inv_h2) {
  const Real margin = settings_.contact_margin;
  const Real share = inv_h2 / substeps_;
  const std::span<const std::array<std::uint32_t, 2>> ends = p.in.field->sample_vertices();
  for (const Pair& pair : p.pairs) {
    const Triangle& tri = triangles_[pair.triangle];
    XpbdParticle* x[3] = {&view.x[tri[0]], &view.x[tri[1]], &view.x[tri[2]]};
    const Real w_inv[3] = {x[0]->w, x[1]->w, x[2]->w};
    if (w_inv[0] + w_inv[1] + w_inv[2] == 0) continue;
    const Vec3 x0 = position(*x[0]), x1 = position(*x[1]), x2 = position(*x[2]);
    const Vec3& a = p.sample_world[pair.sample];
    Vec3 n = (x1 - x0).cross(x2 - x0);
    const Real nn = n.norm();
    if (!(nn > 1e-20)) continue;
    n *= pair.side / nn;
    const Real d = n.dot(a - x0);
    if (d >= margin || d < -p.depth_limit) continue;
    // Barycentric coordinates of a's projection (Ericson, Real-Time Collision Detection §3.4).
    const Vec3 e0 = x1 - x0, e1 = x2 - x0, e2 = a - x0;
    const Real d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1), d20 = e2.dot(e0), d21 = e2.dot(e1);
    const Real den = d00 * d11 - d01 * d01;
    if (!(den > 0)) continue;
    const Real b1 = (d11 * d20 - d01 * d21) / den, b2 = (d00 * d21 - d01 * d20) / den;
    Real w[3] = {1 - b1 - b2, b1, b2};
    if (w[0] < -kInsideFace || w[1] < -kInsideFace || w[2] < -kInsideFace) continue;
    Real sum = 0;
    for (Real& wk : w) {
      wk = std::max(wk, Real{0});
      sum += wk;
    }
    Real denominator = 0;
    for (int k = 0; k < 3; ++k) {
      w[k] /= sum;
      denominator += w[k] * w[k] * w_inv[k];
    }
    if (!(denominator > 0)) continue;
    // A point near a pinned corner would need its free corners moved far (the lever 1/w): no
    // corner moves more than twice the depth in one push; later substeps finish the job.
    Real correction = (margin - d) / denominator;
    Real longest = 0;
    for (int k = 0; k < 3; ++k) longest = std::max(longest, w_inv[k] * w[k] * correction);
    if (longest > 2 * (margin - d)) correction *= 2 * (margin - d) / longest;
    Vec3 moved = Vec3::Zero();  // Σ m_j Δx_j
    const float speed = static_cast<float>(-n.dot(p.in.instrument->velocity_at(a)));
    for (int k = 0; k < 3; ++k) {
      if (w_inv[k] == 0) continue;
      if (moved_.size() < moved_.capacity())
        moved_.push_back({tri[k], static_cast<float>(-n.x()), static_cast<float>(-n.y()), static_cast<float>(-n.z()), speed});
      const Vec3 dx = -(w_inv[k] * w[k] * correction) * n;
      store(*x[k], position(*x[k]) + dx);
      moved += dx / w_inv[k];
      if (touched_stamp_[tri[k]] != stamp_) {
        touched_stamp_[tri[k]] = stamp_;
        ++contacts_;
      }
    }
    p.force -= moved * share;
    p.torque += (a - p.to.translation).cross(-moved * share);
    if (p.points.size() < p.points.capacity()) p.points.push_back({a, n});
    for (const std::uint32_t v : ends[p.samples[pair.sample]]) p.hits[v] = 1;
  }
}

void InstrumentContacts::project_vertices(PerInstrument& p, const XpbdView& view, const Pose& pose,
                                          const Pose& before, Real inv_h2) {
  const Real margin = settings_.contact_margin;
  const Real share = inv_h2 / substeps_;
  const Mat3 r = pose.rotation_matrix();
  const std::span<const Triangle> itri = p.in.instrument->triangles();
  // Beyond the port the shaft is outside the body (Instrument::set_port): a vertex there is not
  // touched, so a shaft backing out lets go of what it carried at the port.
  const Vec3& shaft = p.in.instrument->local_shaft();
  const Real port = p.in.instrument->port_height(pose);
  for (const std::uint32_t v : p.candidates) {
    XpbdParticle& particle = view.x[v];
    if (particle.w == 0.f) continue;
    const Vec3 x = position(particle);
    const Vec3 q = r.transpose() * (x - pose.translation);
    if (shaft.dot(q) > port) continue;
    if (p.in.field->lower_bound(q) >= margin) continue;
    const SignedDistanceResult res = p.in.field->query(q, p.hint[v]);
    p.hint[v] = res.triangle;
    if (!(res.distance < margin)) continue;
    // Outward direction at the closest point: away from it when outside, toward it inside.
    Vec3 out = q - res.closest_point;
    const Real gap = out.norm();
    out = gap > 1e-12 ? (res.distance < 0 ? -out : out) / gap : res.pseudonormal;
    Real depth = margin - res.distance;  // how far along `out` the vertex must go
    const Vec3 q_before = to_local(before, position(view.previous[v]));
    if (res.distance < 0) {
      // Inside now: if it was outside at the substep's start, it leaves by the side it came in
      // (the plane of the feature it was nearest to then), not by the nearest side, which for
      // a vertex past the middle of a thin wire is the far one.
      const SignedDistanceResult was = p.in.field->query(q_before, res.triangle);
      if (was.distance >= 0) {
        Vec3 n_before = q_before - was.closest_point;
        const Real len = n_before.norm();
        n_before = len > 1e-12 ? Vec3(n_before / len) : was.pseudonormal;
        const Real height = n_before.dot(q - was.closest_point);
        if (height < margin && n_before.squaredNorm() > 0) {
          out = n_before;
          depth = margin - height;
        }
      }
    }
    const Vec3 normal = r * out;
    const Vec3 push = depth * normal;
    Vec3 moved = x + push;
    // Friction: the slip relative to the instrument over this substep, tangential part.
    const Vec3 slip = r * (q + out * depth - q_before);
    const Vec3 tangential = slip - slip.dot(normal) * normal;
    const Real t = tangential.norm(), n = push.norm();
    if (t <= settings_.friction_static * n)
      moved -= tangential;
    else if (t > 0)
      moved -= tangential * std::min(Real{1}, settings_.friction_kinetic * n / t);
    store(particle, moved);
    if (moved_.size() < moved_.capacity())
      moved_.push_back({v, static_cast<float>(normal.x()), static_cast<float>(normal.y()), static_cast<float>(normal.z()),
                        static_cast<float>(normal.dot(p.in.instrument->velocity_at(moved)))});
    const Vec3 impulse = (moved - x) * (view.masses[v] * share);
    if (p.points.size() < p.points.capacity()) p.points.push_back({moved, -normal});
    p.force -= impulse;
    p.torque += (moved - p.to.translation).cross(-impulse);
    if (res.triangle < itri.size())
      for (const std::uint32_t iv : itri[res.triangle]) p.hits[iv] = 1;
    if (touched_stamp_[v] != stamp_) {
      touched_stamp_[v] = stamp_;
      ++contacts_;
    }
  }
}

void InstrumentContacts::solve_velocities(std::span<XpbdParticle> velocities) {
  for (const Moved& m : moved_) {
    XpbdParticle& u = velocities[m.vertex];
    const float along = u.x * m.nx + u.y * m.ny + u.z * m.nz;
    if (along <= m.speed) continue;
    const float excess = along - m.speed;
    u.x -= excess * m.nx;
    u.y -= excess * m.ny;
    u.z -= excess * m.nz;
  }
}

}  // namespace trocar

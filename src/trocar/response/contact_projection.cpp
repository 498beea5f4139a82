#include "trocar/response/contact_projection.h"

#include <algorithm>
#include <cmath>

#include "trocar/geometry/barycentric.h"

namespace trocar {

void ContactProjector::reset(std::size_t vertex_count, std::span<const Triangle> triangles,
                             std::size_t instrument_vertices) {
  step_ = 1;
  hits_.assign(instrument_vertices, 0);
  mean_edge_ = -1;
  vertex_first_.assign(vertex_count + 1, 0);
  for (const Triangle& t : triangles)
    for (const std::uint32_t v : t)
      if (v < vertex_count) ++vertex_first_[v + 1];
  for (std::size_t v = 0; v < vertex_count; ++v) vertex_first_[v + 1] += vertex_first_[v];
  vertex_faces_.assign(vertex_first_.back(), 0);
  std::vector<std::uint32_t> fill(vertex_first_.begin(), vertex_first_.end() - 1);
  for (std::uint32_t k = 0; k < triangles.size(); ++k)
    for (const std::uint32_t v : triangles[k])
      if (v < vertex_count) vertex_faces_[fill[v]++] = k;
  face_step_.assign(triangles.size(), 0);
  candidates_.clear();
  candidates_.reserve(vertex_count);
  near_step_.assign(vertex_count, 0);
  last_local_.assign(vertex_count, Vec3::Zero());
  last_point_.assign(vertex_count, Vec3::Zero());
  last_normal_.assign(vertex_count, Vec3::Zero());
  last_distance_.assign(vertex_count, 0);
  hint_.assign(vertex_count, MeshDistance::kNoTriangle);
  moved_step_.assign(vertex_count, 0);
  start_.assign(vertex_count, Vec3::Zero());
  moved_.clear();
  moved_.reserve(vertex_count);
  push_.assign(vertex_count, Vec3::Zero());
  push_length_.assign(vertex_count, 0);
  pushed_.clear();
  pushed_.reserve(vertex_count);
  round_moved_.clear();
  round_moved_.reserve(vertex_count);
}

void ContactProjector::size_for(const InstrumentField& field) {
  const std::size_t samples = field.samples().size();
  world_samples_.assign(samples, Vec3::Zero());
  active_samples_.clear();
  active_samples_.reserve(samples);
  grid_start_.reserve(4097);
  grid_fill_.reserve(4097);
  grid_samples_.reserve(samples);
}

void ContactProjector::mark_moved(std::uint32_t v, const Vec3& x) {
  if (moved_step_[v] == step_) return;
  moved_step_[v] = step_;
  start_[v] = x;
  moved_.push_back(v);
}

ProjectionStats ContactProjector::project(const Instrument& instrument, const InstrumentField& field,
                                          std::span<const Contact> contacts, std::uint32_t instrument_object,
                                          std::uint32_t tissue_object, const Grasp& grasp,
                                          const ProjectedTissue& tissue, Real thickness, Real dt,
                                          const ResponseSettings& settings) {
  ++step_;
  ProjectionStats stats;
  const std::size_t n = tissue.positions.size();
  std::fill(hits_.begin(), hits_.end(), std::uint8_t{0});
  if (field.empty() || n == 0 || n != near_step_.size() || !(dt > 0)) return stats;
  moved_.clear();
  // How far the instrument's surface can sweep over one step relative to a resting point: its
  // origin's speed plus ω times the farthest point of its box. Twice that, plus the margin and a
  // grid cell, is the distance within which a vertex is queried exactly and its nearest feature
  // recorded for the next step's previous-plane rule.
  const Real radius = std::max(field.box().min.norm(), field.box().max.norm());
  const Real sweep = (instrument.linear_velocity().norm() + instrument.angular_velocity().norm() * radius) * dt;
  cull_ = settings.contact_margin + 2 * sweep + field.cell_size();
  const Aabb box = instrument.world_obb().bounds().inflated(std::max(cull_, 2 * std::max(mean_edge_, Real{0})));
  candidates_.clear();
  for (std::uint32_t v = 0; v < n; ++v)
    if (tissue.fixed[v] == 0 && box.contains(tissue.positions[v]) && !grasp.is_grasped(v) &&
        !instrument.outside_body(tissue.positions[v]))  // beyond the port: outside the body
      candidates_.push_back(v);
  stats.candidates = static_cast<std::uint32_t>(candidates_.size());
  if (candidates_.empty() && contacts.empty()) return stats;

  if (mean_edge_ < 0) {
    // Once, from the first positions: the reach of pass (b)'s nearby triangles.
    Real sum = 0;
    std::size_t count = 0;
    for (const Triangle& t : tissue.triangles) {
      if (t[0] >= n || t[1] >= n || t[2] >= n) continue;
      sum += (tissue.positions[t[0]] - tissue.positions[t[1]]).norm();
      ++count;
    }
    mean_edge_ = count > 0 ? sum / static_cast<Real>(count) : 0;
  }
  top_ = instrument.top_world();
  project_vertices(instrument, field, tissue, settings, true, stats);
  // Gauss–Seidel rounds of (b) then (a): a face push can move a vertex into the tool and a
  // vertex projection can lift a face over a sample (3 rounds: lobe-8K press p99 0.8 → 0.25 mm).
  place_samples(instrument, field, contacts, instrument_object, tissue_object, tissue, thickness + 2 * sweep);
  for (int round = 0; round < std::max(settings.projection_rounds, 1); ++round) {
    push_faces(instrument, field, contacts, instrument_object, tissue_object, grasp, tissue, settings,
               thickness + 2 * sweep, stats);
    project_vertices(instrument, field, tissue, settings, false, stats);
  }

  // Inelastic contact: the correction becomes velocity. The force that moved vertex i by Δx_i
  // over dt (from rest relative to its integrated path) is m_i Δx_i / dt²; the instrument feels
  // the opposite.
  const Vec3 origin = instrument.pose().translation;
  const Real inv_dt = 1 / dt;
  for (const std::uint32_t v : moved_) {
    const Vec3 delta = tissue.positions[v] - start_[v];
    tissue.velocities[v] += delta * inv_dt;
    const Vec3 f = -tissue.masses[v] * delta * (inv_dt * inv_dt);
    stats.force += f;
    stats.torque += (tissue.positions[v] - origin).cross(f);
    stats.max_correction = std::max(stats.max_correction, delta.norm());
  }
  return stats;
}

void ContactProjector::project_vertices(const Instrument& instrument, const InstrumentField& field,
                                        const ProjectedTissue& tissue, const ResponseSettings& settings, bool first,
                                        ProjectionStats& stats) {
  const Mat3 r = instrument.pose().rotation_matrix();
  const Mat3 rt = r.transpose();
  const Vec3& t = instrument.pose().translation;
  const Real margin = settings.contact_margin;
  for (const std::uint32_t v : first ? std::span<const std::uint32_t>(candidates_) : std::span<const std::uint32_t>(round_moved_)) {
    Vec3& x = tissue.positions[v];
    if (!x.allFinite()) continue;
    const Vec3 q = rt * (x - t);
    if (field.lower_bound(q) > cull_) continue;  // far from the instrument: nothing to do or record
    SignedDistanceResult hit = field.query(q, hint_[v]);
    hint_[v] = hit.triangle;
    const bool was_outside = near_step_[v] + 1 == step_ && last_distance_[v] >= 0;
    bool moved = false;
    if (hit.distance < margin) {
      Vec3 target = hit.closest_point + margin * hit.pseudonormal;
      Vec3 normal = hit.pseudonormal;
      if (first && was_outside) {
        // Leave by the side it came in: onto the plane of last step's nearest feature, unless
        // that plane is not outside the instrument here (a concave part), then the nearest point.
        const Real s = (q - last_point_[v]).dot(last_normal_[v]);
        if (s < margin) {
          const Vec3 on_plane = q + (margin - s) * last_normal_[v];
          const SignedDistanceResult check = field.query(on_plane, hit.triangle);
          if (check.distance >= 0.5 * margin) {
            target = on_plane;
            normal = last_normal_[v];
          } else {  // from the plane's point, still on the side it came in
            target = check.closest_point + margin * check.pseudonormal;
            normal = check.pseudonormal;
          }
        }
      }
      if (first && was_outside && settings.friction_static > 0) {
        // Friction on the position (Macklin et al., "Unified particle physics", SIGGRAPH 2014,
        // §6.1): the motion relative to the instrument since the end of the last step, along
        // the surface, is undone while it is within μs × the normal correction (the surface
        // sticks to a sliding instrument instead of slipping around a thin one), else shortened
        // by μk × the normal correction.
        const Real dn = (target - q).norm();
        const Vec3 rel = target - last_local_[v];
        const Vec3 tangent = rel - rel.dot(normal) * normal;
        const Real length = tangent.norm();
        if (length <= settings.friction_static * dn)
          target -= tangent;
        else
          target -= tangent * std::min(Real{1}, settings.friction_kinetic * dn / length);
      }
      mark_moved(v, x);
      x = t + r * target;
      moved = true;
      if (first) ++stats.projected;
    }
    {  // the end-of-step record (each round overwrites it for the vertices it looked at)
      near_step_[v] = step_;
      last_local_[v] = rt * (x - t);
      last_point_[v] = hit.closest_point;
      last_normal_[v] = hit.pseudonormal;
      last_distance_[v] = moved ? margin : hit.distance;
    }
  }
}

void ContactProjector::place_samples(const Instrument& instrument, const InstrumentField& field,
                                     std::span<const Contact> contacts, std::uint32_t instrument_object,
                                     std::uint32_t tissue_object, const ProjectedTissue& tissue, Real depth_limit) {
  const std::size_t n = tissue.positions.size();
  const std::size_t nt = tissue.triangles.size();
  const Mat3 r = instrument.pose().rotation_matrix();
  const Vec3& t = instrument.pose().translation;
  // The instrument's points near the tissue's candidates (the box of the candidate vertices and
  // the contacts' faces, grown by the depth limit), in the world.
  Aabb near;
  for (const std::uint32_t v : candidates_) near.expand(tissue.positions[v]);
  for (const Contact& c : contacts)
    if (c.kind == ContactKind::kInstrumentTissue && c.object_a == instrument_object &&
        c.object_b == tissue_object && c.triangle_b < nt)
      for (const std::uint32_t v : tissue.triangles[c.triangle_b])
        if (v < n) near.expand(tissue.positions[v]);
  near = near.inflated(depth_limit);
  const std::span<const Vec3> samples = field.samples();
  if (world_samples_.size() != samples.size()) size_for(field);  // without size_for(): allocates once
  active_samples_.clear();
  Aabb active;
  if (!near.is_empty())
    for (std::uint32_t k = 0; k < samples.size(); ++k) {
      const Vec3 p = t + r * samples[k];
      if (!near.contains(p) || instrument.outside_body(p)) continue;
      world_samples_[k] = p;
      active.expand(p);
      active_samples_.push_back(k);
    }
  // A uniform grid over the active samples (counting sort into cells of about a tissue edge,
  // at most kMaxCells), so that a face visits only the samples in the cells its box covers.
  grid_box_ = active;
  grid_n_ = {0, 0, 0};
  if (active.is_empty()) return;
  constexpr std::size_t kMaxCells = 4096;
  const Vec3 size = active.size();
  grid_cell_ = std::max({std::max(mean_edge_, Real{1e-4}), size.maxCoeff() / 64});
  while (true) {
    for (int k = 0; k < 3; ++k) grid_n_[k] = static_cast<std::size_t>(size[k] / grid_cell_) + 1;
    if (grid_n_[0] * grid_n_[1] * grid_n_[2] <= kMaxCells) break;
    grid_cell_ *= 1.5;
  }
  const std::size_t cells = grid_n_[0] * grid_n_[1] * grid_n_[2];
  grid_start_.assign(cells + 1, 0);  // sized kMaxCells + 1 at most: reserved in reset
  for (const std::uint32_t k : active_samples_) ++grid_start_[grid_cell_of(world_samples_[k]) + 1];
  for (std::size_t c = 0; c < cells; ++c) grid_start_[c + 1] += grid_start_[c];
  grid_fill_.assign(grid_start_.begin(), grid_start_.end() - 1);
  grid_samples_.resize(active_samples_.size());
  for (const std::uint32_t k : active_samples_) grid_samples_[grid_fill_[grid_cell_of(world_samples_[k])]++] = k;
}

void ContactProjector::push_faces(const Instrument& instrument, const InstrumentField& field,
                                  std::span<const Contact> contacts, std::uint32_t instrument_object,
                                  std::uint32_t tissue_object, const Grasp& grasp, const ProjectedTissue& tissue,
                                  const ResponseSettings& settings, Real depth_limit, ProjectionStats& stats) {
  ++face_round_;
  const std::size_t n = tissue.positions.size();
  const std::size_t nt = tissue.triangles.size();
  const Mat3 rt = instrument.pose().rotation_matrix().transpose();
  const Vec3& t = instrument.pose().translation;
  if (active_samples_.empty()) return;
  for (const Contact& c : contacts) {
    if (c.kind != ContactKind::kInstrumentTissue || c.object_a != instrument_object || c.object_b != tissue_object)
      continue;
    if (c.triangle_b < nt) push_face(field, c.triangle_b, grasp, tissue, settings, depth_limit, stats);
  }
  const Real reach = cull_ + 2 * mean_edge_;
  for (const std::uint32_t v : candidates_) {
    if (v >= n || !tissue.positions[v].allFinite()) continue;
    if (field.lower_bound(rt * (tissue.positions[v] - t)) > reach) continue;
    for (std::uint32_t k = vertex_first_[v]; k < vertex_first_[v + 1]; ++k)
      push_face(field, vertex_faces_[k], grasp, tissue, settings, depth_limit, stats);
  }
  round_moved_.clear();
  for (const std::uint32_t v : pushed_) {
    mark_moved(v, tissue.positions[v]);
    round_moved_.push_back(v);
    const Real direction = push_[v].norm();
    if (direction > 0) tissue.positions[v] += (push_length_[v] / direction) * push_[v];
    push_[v].setZero();
    push_length_[v] = 0;
  }
  pushed_.clear();
}

void ContactProjector::push_face(const InstrumentField& field, std::uint32_t triangle, const Grasp& grasp,
                                 const ProjectedTissue& tissue, const ResponseSettings& settings, Real depth_limit,
                                 ProjectionStats& stats) {
  if (face_step_[triangle] == face_round_) return;  // once per round
  face_step_[triangle] = face_round_;
  const std::size_t n = tissue.positions.size();
  const Triangle& tb = tissue.triangles[triangle];
  if (tb[0] >= n || tb[1] >= n || tb[2] >= n) return;
  const Vec3& b0 = tissue.positions[tb[0]];
  const Vec3& b1 = tissue.positions[tb[1]];
  const Vec3& b2 = tissue.positions[tb[2]];
  const Vec3 cross = (b1 - b0).cross(b2 - b0);
  const Real area2 = cross.norm();
  if (!(area2 > 0)) return;
  const Vec3 n_out = cross / area2;
  // The far side of the organ from the instrument (its top vertex inside this face's plane) is
  // never pushed: that is where a pierced or deeply pressed organ's other surface is.
  if (settings.pierce_filter && n_out.dot(top_ - b0) < 0) return;
  Aabb face;
  face.expand(b0);
  face.expand(b1);
  face.expand(b2);
  // The prism under the face, boxed: grown along each axis by the depth limit's share of the
  // normal there (a horizontal face grows only downward-and-up in z), plus a little for the
  // barycentric tolerance below.
  const Vec3 grow = depth_limit * n_out.cwiseAbs() + Vec3::Constant(0.02 * std::max(mean_edge_, Real{0}) + 1e-6);
  face.min -= grow;
  face.max += grow;
  const Real margin = settings.contact_margin;
  if (!face.overlaps(grid_box_)) return;
  std::array<std::size_t, 3> lo{}, hi{};
  for (int k = 0; k < 3; ++k) {
    const Real a = std::max(Real{0}, (face.min[k] - grid_box_.min[k]) / grid_cell_);
    const Real b = std::max(Real{0}, (face.max[k] - grid_box_.min[k]) / grid_cell_);
    lo[k] = std::min(static_cast<std::size_t>(a), grid_n_[k] - 1);
    hi[k] = std::min(static_cast<std::size_t>(b), grid_n_[k] - 1);
  }
  for (std::size_t cz = lo[2]; cz <= hi[2]; ++cz)
    for (std::size_t cy = lo[1]; cy <= hi[1]; ++cy)
      for (std::size_t cx = lo[0]; cx <= hi[0]; ++cx) {
        const std::size_t cell = (cz * grid_n_[1] + cy) * grid_n_[0] + cx;
        for (std::uint32_t g = grid_start_[cell]; g < grid_start_[cell + 1]; ++g)
          push_sample(grid_samples_[g], tb, n_out, b0, b1, b2, face, grasp, tissue, field, margin, depth_limit, stats);
      }
}

void ContactProjector::push_sample(std::uint32_t ks, const Triangle& tb, const Vec3& n_out, const Vec3& b0,
                                   const Vec3& b1, const Vec3& b2, const Aabb& face, const Grasp& grasp,
                                   const ProjectedTissue& tissue, const InstrumentField& field, Real margin,
                                   Real depth_limit, ProjectionStats& stats) {
  const Vec3& a = world_samples_[ks];
  if (!face.contains(a)) return;
    const Real d = n_out.dot(a - b0);
    if (!(d < 0) || d < -depth_limit) return;
    Vec3 w = barycentric(a - d * n_out, b0, b1, b2);
    // Over this face, to a small tolerance so that a vertex under the crease between two faces is
    // answered by both (each tissue vertex keeps the longer push).
    if (!(w.minCoeff() >= -0.02)) return;
    w = w.cwiseMax(0);
    w /= w.sum();
    for (int k = 0; k < 3; ++k)
      if (tissue.fixed[tb[k]] != 0 || grasp.is_grasped(tb[k])) w[k] = 0;
    const Real w2 = w.squaredNorm();
    if (!(w2 > 0)) return;
    const Vec3 delta = (d - margin) * n_out;
    for (int k = 0; k < 3; ++k) {
      if (w[k] <= 0) return;
      const std::uint32_t v = tb[k];
      const Vec3 push = (w[k] / w2) * delta;
      const Real length = push.norm();
      if (push_length_[v] == 0) pushed_.push_back(v);
      push_[v] += w[k] * push;  // the direction: the weighted mean of the pushes
      push_length_[v] = std::max(push_length_[v], length);  // the length: the longest
    }
    ++stats.face_pushes;
    for (const std::uint32_t iv : field.sample_vertices()[ks])
      if (iv < hits_.size()) hits_[iv] = 1;
}

}  // namespace trocar

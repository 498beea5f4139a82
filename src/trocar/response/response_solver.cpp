#include "trocar/response/response_solver.h"

#include <algorithm>
#include <cmath>

namespace trocar {

void InstrumentLoad::clamp(Real max_force) {
  const Real mag = raw_force.norm();
  Real scale = 1;
  if (max_force > 0 && mag > max_force) scale = max_force / mag;
  clamped = scale < 1;
  force = scale * raw_force;
  torque = scale * raw_torque;
}

Real correction_gate(Real approach_speed, Real correction_speed) {
  if (!(correction_speed > 0)) return 1;
  return std::clamp(approach_speed / correction_speed, Real{0}, Real{1});
}

void ResponseSolver::reset(std::size_t tissue_vertex_count) {
  grasp_.reset(tissue_vertex_count);
  correction_.assign(tissue_vertex_count, Vec3::Zero());
  correction_weight_.assign(tissue_vertex_count, 0);
  touched_.clear();
  touched_.reserve(tissue_vertex_count);
}

void ResponseSolver::remodel(std::span<const std::uint32_t> vertex_origin) {
  grasp_.remodel(vertex_origin);
  correction_.assign(vertex_origin.size(), Vec3::Zero());
  correction_weight_.assign(vertex_origin.size(), 0);
  touched_.clear();
  touched_.reserve(vertex_origin.size());
}

ResponseStats ResponseSolver::apply(std::span<const Contact> contacts, std::uint32_t instrument_object,
                                    std::uint32_t tissue_object, const Instrument& instrument,
                                    const TissueView& tissue, TissueLoads& loads, InstrumentLoad& load) {
  ResponseStats stats;
  const bool corrects =
      settings_.method == ResponseMethod::kProject || settings_.method == ResponseMethod::kPrimitive;
  for (const std::uint32_t v : touched_) {
    correction_[v].setZero();
    correction_weight_[v] = 0;
  }
  touched_.clear();
  const bool closed = instrument.jaw() >= settings_.grasp_closure;
  if (!closed && !grasp_.held().empty()) grasp_.release_all();

  const std::span<const Vec3> ix = instrument.world_positions();
  const std::span<const Triangle> itri = instrument.triangles();
  const Obb& box = instrument.world_obb();
  const Vec3& top = instrument.top_world();
  const Vec3 origin = instrument.pose().translation;
  const std::span<const Vec3> normal_span =
      settings_.method == ResponseMethod::kNormal ? ix : std::span<const Vec3>{};
  const std::size_t nv = tissue.positions.size();
  const bool have_v = tissue.velocities.size() == nv;

  ContactTriangles tri;
  for (const Contact& c : contacts) {
    if (c.kind != ContactKind::kInstrumentTissue || c.object_a != instrument_object || c.object_b != tissue_object)
      continue;
    if (c.triangle_a >= itri.size() || c.triangle_b >= tissue.triangles.size()) continue;
    ++stats.considered;
    const Triangle& ta = itri[c.triangle_a];
    const Triangle& tb = tissue.triangles[c.triangle_b];
    if (tb[0] >= nv || tb[1] >= nv || tb[2] >= nv) continue;
    // A face wholly beyond the port is outside the body (Instrument::set_port): untouched.
    if (instrument.outside_body(tissue.positions[tb[0]]) && instrument.outside_body(tissue.positions[tb[1]]) &&
        instrument.outside_body(tissue.positions[tb[2]]))
      continue;

    // Step 10: closed jaws hold what they touch; held triangles get no penalty.
    if (closed && instrument.is_jaw_triangle(c.triangle_a)) {
      for (const std::uint32_t v : tb) grasp_.grab(v, tissue.positions[v], c.triangle_a, instrument);
    }
    if (grasp_.is_grasped(tb[0]) && grasp_.is_grasped(tb[1]) && grasp_.is_grasped(tb[2])) {
      ++stats.by_status[static_cast<std::size_t>(ContactStatus::kGrasped)];
      continue;
    }

    if (settings_.method == ResponseMethod::kSdf) {
      // Contact as a constraint: ContactProjector moves the tissue after its integration; no
      // penalty force here. The contact counts as applied (the projection answers it).
      ++stats.by_status[static_cast<std::size_t>(ContactStatus::kApplied)];
      continue;
    }
    for (int i = 0; i < 3; ++i) {
      tri.a[i] = ix[ta[i]];
      tri.va[i] = instrument.velocity_at(tri.a[i]);
      tri.b[i] = tissue.positions[tb[i]];
      tri.vb[i] = have_v ? tissue.velocities[tb[i]] : Vec3::Zero();
    }
    const ContactResponse r = respond_contact(tri, box, &top, normal_span, settings_);
    ++stats.by_status[static_cast<std::size_t>(r.status)];
    if (r.status != ContactStatus::kApplied) continue;
    last_ = r;
    stats.max_depth = std::max(stats.max_depth, r.depth);

    // Barycentric distribution; vertices held by the jaws get nothing (partially held triangle).
    Vec3 w = r.weights_b;
    for (int i = 0; i < 3; ++i) {
      if (grasp_.is_grasped(tb[i])) w[i] = 0;
    }
    for (int i = 0; i < 3; ++i) loads.add_force(tb[i], w[i] * r.force);
    // Newton's third law on what was applied: −F·Σw at P, torque about the pose origin.
    const Vec3 applied = w.sum() * r.force;
    load.raw_force -= applied;
    load.raw_torque += (r.point - origin).cross(-applied);
    if (r.force.squaredNorm() > 0) {
      ContactJacobian j;
      j.vertices = tb;
      j.weights = {w[0], w[1], w[2]};
      j.normal = r.normal_in;
      j.stiffness = settings_.stiffness;
      j.damping = settings_.damping;
      loads.contacts.push_back(j);
    }
    if (corrects) {
      const Real gate = correction_gate(instrument.velocity_at(r.point).dot(r.normal_in), settings_.correction_speed);
      for (int i = 0; i < 3; ++i) {
        if (w[i] <= 0) continue;
        const std::uint32_t v = tb[i];
        if (correction_weight_[v] == 0) touched_.push_back(v);
        correction_[v] += (gate * w[i]) * r.deformation;
        correction_weight_[v] += w[i];
      }
    }
  }
  load.clamp(settings_.max_force);
  return stats;
}

void ResponseSolver::apply_corrections(std::span<Vec3> positions) const {
  for (const std::uint32_t v : touched_) {
    if (v >= positions.size()) continue;
    positions[v] += correction_[v] / std::max(Real{1}, correction_weight_[v]);
  }
}

}  // namespace trocar

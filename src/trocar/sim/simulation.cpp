#include "trocar/sim/simulation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numeric>

#include "trocar/core/timer.h"
#include "trocar/tissue/forces.h"

namespace trocar {
namespace {

constexpr Real kUnknown = std::numeric_limits<Real>::quiet_NaN();     ///< no measurement yet
constexpr Real kOutside = std::numeric_limits<Real>::infinity();      ///< outside the tissue's box
/// Growth of a tissue's bounding box before it decides that a vertex is outside the tissue (m):
/// far above the rounding of a signed distance (~1e-17 m at organ scale), far below a contact.
constexpr Real kBoxSlack = 1e-9;

CollisionDetector make_detector(const SimulationSettings& s) {
  if (s.broad_phase == BroadPhaseKind::kOhc) {
    OhcSettings ohc;
    ohc.cell_size = s.cell_size;
    return CollisionDetector(ohc);
  }
  return CollisionDetector(s.broad_phase);
}

/// FNV-1a over the 8 bytes of one double.
void hash_real(std::uint64_t& h, Real x) {
  unsigned char bytes[sizeof(Real)];
  std::memcpy(bytes, &x, sizeof bytes);
  for (unsigned char b : bytes) {
    h ^= b;
    h *= 0x100000001b3ull;
  }
}

/// Instrument vertices waiting to be queried together (MeshDistance::signed_distances): one
/// tree walk per batch instead of per vertex. 16 nearby vertices per walk measured best on the
/// probe–liver press (4: no gain, 32: none over 16).
struct QueryBatch {
  static constexpr std::size_t kSize = 16;
  std::array<Vec3, kSize> points;
  std::array<std::uint32_t, kSize> hints;     ///< nearest triangle last time, then now
  std::array<std::uint32_t, kSize> vertices;  ///< instrument vertex ids
  std::array<SignedDistanceResult, kSize> results;
  std::size_t count = 0;
};

/// Vertex ids in a spatially coherent order, so that consecutive vertices make compact batches:
/// recursive median splits along the longest axis of the points' box (ties by id).
void coherent_order(std::span<const Vec3> points, std::span<std::uint32_t> ids) {
  if (ids.size() <= 2) return;
  Aabb box;
  for (const std::uint32_t v : ids) box.expand(points[v]);
  Eigen::Index axis = 0;
  box.size().maxCoeff(&axis);
  const auto mid = ids.begin() + static_cast<std::ptrdiff_t>(ids.size() / 2);
  std::nth_element(ids.begin(), mid, ids.end(), [&](std::uint32_t a, std::uint32_t b) {
    return points[a][axis] < points[b][axis] || (points[a][axis] == points[b][axis] && a < b);
  });
  coherent_order(points, ids.first(ids.size() / 2));
  coherent_order(points, ids.subspan(ids.size() / 2));
}

/// True when every coordinate is finite. ±inf and NaN are the doubles whose 11 exponent bits are
/// all ones; adding one unit of the exponent's last bit carries those, and only those, into the
/// top bit. And, add and or vectorise with plain SSE2 (a per-coordinate test did not).
bool all_finite(std::span<const Vec3> points) {
  static_assert(sizeof(Vec3) == 3 * sizeof(Real), "Vec3 holds 3 contiguous coordinates");
  constexpr std::uint64_t kExponent = 0x7ff0000000000000ull;
  constexpr std::uint64_t kExponentOne = 0x0010000000000000ull;
  if (points.empty()) return true;
  const Real* x = points.data()->data();
  std::uint64_t carried = 0;
  for (std::size_t i = 0; i < 3 * points.size(); ++i) {
    std::uint64_t bits;
    std::memcpy(&bits, x + i, sizeof bits);
    carried |= (bits & kExponent) + kExponentOne;
  }
  return (carried >> 63) == 0;
}

/// True when some point lies in box.
bool any_inside(std::span<const Vec3> points, const Aabb& box) {
  return std::any_of(points.begin(), points.end(), [&](const Vec3& p) { return box.contains(p); });
}

/// True when a and b hold the same vertices, bit for bit.
bool same_bits(std::span<const Vec3> a, std::span<const Vec3> b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size_bytes()) == 0;
}

void hash_vec(std::uint64_t& h, const Vec3& v) {
  for (int k = 0; k < 3; ++k) hash_real(h, v[k]);
}

}  // namespace

Simulation::Simulation(World world, const SimulationSettings& settings)
    : world_(std::move(world)), settings_(settings), detector_(make_detector(settings)) {
  const std::size_t ni = world_.instruments.size();
  const std::size_t nt = world_.tissues.size();
  commands_.resize(ni);
  for (InstrumentBody& body : world_.instruments) {
    const MotionSample s = body.motion.sample(0);
    body.instrument.reset_pose(s.pose);
    body.instrument.set_jaw(s.jaw);
  }
  for (const InstrumentBody& body : world_.instruments)
    objects_.push_back({ObjectRole::kInstrument, body.instrument.world_positions(), body.instrument.triangles()});
  for (const auto& tissue : world_.tissues)
    objects_.push_back({ObjectRole::kTissue, tissue->state.positions, tissue->settings.triangles});
  for (const RigidBody& rigid : world_.rigids)
    objects_.push_back({ObjectRole::kRigid, rigid.mesh.positions, rigid.mesh.triangles});

  solvers_.reserve(ni * nt);
  for (std::size_t i = 0; i < ni; ++i)
    for (std::size_t t = 0; t < nt; ++t) {
      solvers_.emplace_back(settings_.response);
      solvers_.back().reset(world_.tissues[t]->settings.vertex_count());
    }
  bool any_solver_contact = false;
  for (const auto& tissue : world_.tissues) any_solver_contact |= tissue->integrator.kind() == IntegratorKind::kXpbd;
  if (settings_.response.method == ResponseMethod::kSdf || any_solver_contact)
    for (const InstrumentBody& body : world_.instruments) fields_.emplace_back(body.instrument.local_mesh());
  // Tissues on the xpbd integrator solve their instrument contacts inside its substeps.
  solver_contacts_.resize(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    TissueBody& tissue = *world_.tissues[t];
    if (tissue.integrator.kind() != IntegratorKind::kXpbd) continue;
    std::vector<SolverInstrument> inputs;
    for (std::size_t i = 0; i < ni; ++i)
      inputs.push_back({&world_.instruments[i].instrument, &fields_[i], world_.instruments[i].thickness});
    solver_contacts_[t] = std::make_unique<InstrumentContacts>();
    solver_contacts_[t]->reset(tissue.settings.rest_positions, tissue.settings.triangles, tissue.settings.closed,
                               inputs, settings_.response);
    tissue.integrator.set_contacts(solver_contacts_[t].get());
  }
  if (settings_.response.method == ResponseMethod::kSdf) {
    projectors_.resize(ni * nt);
    for (std::size_t i = 0; i < ni; ++i)
      for (std::size_t t = 0; t < nt; ++t) {
        projectors_[i * nt + t].reset(world_.tissues[t]->settings.vertex_count(), world_.tissues[t]->settings.triangles,
                                      world_.instruments[i].instrument.world_positions().size());
        projectors_[i * nt + t].size_for(fields_[i]);
      }
  }
  loads_.resize(ni);
  instrument_metrics_.resize(ni);
  distances_.resize(nt);
  start_distances_.resize(nt);
  start_positions_.resize(nt);
  sheets_.resize(nt);
  if (settings_.measure_penetration)
    for (std::size_t t = 0; t < nt; ++t) {
      const TissueBody& tissue = *world_.tissues[t];
      if (tissue.settings.triangles.empty()) continue;
      distances_[t] = std::make_unique<MeshDistance>(tissue.state.positions, tissue.settings.triangles);
      start_distances_[t] = std::make_unique<MeshDistance>(tissue.state.positions, tissue.settings.triangles);
      start_positions_[t] = tissue.state.positions;
      if (!tissue.settings.closed) sheets_[t] = SheetBoundary(tissue.state.positions, tissue.settings.triangles);
    }
  reach_.resize(ni);
  for (std::size_t i = 0; i < ni; ++i) {
    const Instrument& instrument = world_.instruments[i].instrument;
    for (const Vec3& p : instrument.world_positions())
      reach_[i] = std::max(reach_[i], (p - instrument.pose().translation).norm());
  }
  previous_distance_.resize(ni * nt);
  through_.resize(ni * nt);
  nearest_triangle_.resize(ni * nt);
  touched_.resize(ni);
  query_order_.resize(ni);
  for (std::size_t i = 0; i < ni; ++i) {
    const std::span<const Vec3> points = world_.instruments[i].instrument.world_positions();
    const std::size_t nv = points.size();
    touched_[i].assign(nv, 0);
    query_order_[i].resize(nv);
    std::iota(query_order_[i].begin(), query_order_[i].end(), std::uint32_t{0});
    coherent_order(points, query_order_[i]);
    for (std::size_t t = 0; t < nt; ++t) {
      previous_distance_[i * nt + t].assign(nv, kUnknown);
      through_[i * nt + t].assign(nv, 0);
      nearest_triangle_[i * nt + t].assign(nv, MeshDistance::kNoTriangle);
    }
  }
  contacts_.reserve(1024);
  std::size_t most_triangles = 0;
  for (std::size_t t = 0; t < nt; ++t)
    if (distances_[t]) most_triangles = std::max(most_triangles, world_.tissues[t]->settings.triangles.size());
  query_scratch_ = MeshDistance::BatchScratch(most_triangles);
}

void Simulation::command_instrument(std::size_t i, const Pose& pose, Real jaw) {
  commands_[i].active = true;
  commands_[i].sample.pose = pose;
  commands_[i].sample.jaw = jaw;
}

void Simulation::place_instrument(std::size_t i, const Pose& pose, Real jaw) {
  world_.instruments[i].instrument.reset_pose(pose);
  world_.instruments[i].instrument.set_jaw(jaw);
  command_instrument(i, pose, jaw);
}

void Simulation::release_instrument(std::size_t i) { commands_[i].active = false; }

const StepMetrics& Simulation::step(Real dt) {
  const Timer total;
  const StageTimings zero{};
  metrics_ = StepMetrics{};
  metrics_.timings = zero;

  Timer stage;
  time_ += dt;
  dt_ = dt;
  for (std::size_t i = 0; i < world_.instruments.size(); ++i) {
    InstrumentBody& body = world_.instruments[i];
    const MotionSample s = commands_[i].active ? commands_[i].sample : body.motion.sample(time_);
    body.instrument.move_to(s.pose, dt);
    body.instrument.set_jaw(s.jaw);
  }
  metrics_.timings.motion = stage.microseconds();

  detect();

  stage.restart();
  respond();
  metrics_.timings.response = stage.microseconds();

  stage.restart();
  for (std::size_t t = 0; t < world_.tissues.size(); ++t)  // the surface this step's detection saw
    if (distances_[t]) std::copy(world_.tissues[t]->state.positions.begin(), world_.tissues[t]->state.positions.end(),
                                 start_positions_[t].begin());
  const double copy_us = stage.microseconds();  // for the tunneling metric: counted in metrics

  stage.restart();
  deform(dt);
  metrics_.timings.deformation = stage.microseconds();
  for (std::size_t i = 0; i < loads_.size(); ++i) {
    loads_[i].clamp(settings_.response.max_force);  // the device's force only, never the tissue's
    instrument_metrics_[i] = InstrumentMetrics{loads_[i].force, loads_[i].torque, loads_[i].raw_force};
  }

  stage.restart();
  measure();
  metrics_.timings.metrics = copy_us + stage.microseconds();

  metrics_.time = time_;
  metrics_.step_index = ++steps_;
  metrics_.timings.step = total.microseconds();
  return metrics_;
}

void Simulation::detect() {
  // Detect when the detection clock is due (a small tolerance absorbs the rounding of summed
  // step sizes, so a period equal to k steps detects exactly every k-th step).
  const bool due = settings_.collision_period <= 0 || time_ >= next_detection_ - 1e-6 * settings_.collision_period;
  if (!due) {
    contacts_.clear();
    return;
  }
  if (settings_.collision_period > 0) {
    if (next_detection_ < 0) next_detection_ = time_;  // the first step detects; then every period
    while (next_detection_ <= time_ + 1e-6 * settings_.collision_period) next_detection_ += settings_.collision_period;
  }
  detector_.detect(objects_, contacts_);
  metrics_.detected = true;
  metrics_.timings.broad_phase = detector_.timings().broad_phase_us;
  metrics_.timings.narrow_phase = detector_.timings().narrow_phase_us;
}

void Simulation::respond() {
  const std::size_t ni = world_.instruments.size();
  const std::size_t nt = world_.tissues.size();
  for (auto& tissue : world_.tissues) tissue->loads.clear();
  for (std::size_t i = 0; i < ni; ++i) {
    const Instrument& instrument = world_.instruments[i].instrument;
    InstrumentLoad total;
    for (std::size_t t = 0; t < nt; ++t) {
      TissueBody& tissue = *world_.tissues[t];
      if (solver_contacts_[t]) continue;  // xpbd: contact inside the solver (deform)
      const TissueView view{tissue.state.positions, tissue.state.velocities, tissue.settings.triangles};
      InstrumentLoad pair;
      const ResponseStats stats = solver(i, t).apply(contacts_, static_cast<std::uint32_t>(i),
                                                     static_cast<std::uint32_t>(ni + t), instrument, view,
                                                     tissue.loads, pair);
      metrics_.contacts += stats.considered;
      metrics_.contacts_applied += stats.count(ContactStatus::kApplied);
      total.raw_force += pair.raw_force;
      total.raw_torque += pair.raw_torque;
    }
    loads_[i] = total;
  }
}

void Simulation::deform(Real dt) {
  const std::size_t ni = world_.instruments.size();
  for (std::size_t t = 0; t < world_.tissues.size(); ++t) {
    TissueBody& tissue = *world_.tissues[t];
    const StepStats stats = tissue.integrator.step(tissue.state, tissue.loads, dt);
    metrics_.finite = metrics_.finite && stats.finite;
    metrics_.cg_iterations += static_cast<std::uint32_t>(stats.cg_iterations);
    metrics_.substeps = std::max(metrics_.substeps, static_cast<std::uint32_t>(stats.substeps));
    metrics_.constraint_error = std::max(metrics_.constraint_error, stats.constraint_error);
    if (const InstrumentContacts* contacts = solver_contacts_[t].get()) {
      metrics_.contacts += contacts->contacts();
      metrics_.contacts_applied += contacts->contacts();
      for (std::size_t i = 0; i < ni; ++i) {
        loads_[i].raw_force += contacts->force(i);
        loads_[i].raw_torque += contacts->torque(i);
      }
      continue;
    }
    for (std::size_t i = 0; i < ni; ++i) {
      ResponseSolver& s = solver(i, t);
      s.apply_corrections(tissue.state.positions);
      s.apply_grasp(world_.instruments[i].instrument, tissue.state.positions, tissue.state.velocities);
    }
    if (!projectors_.empty()) {
      const Timer projection;
      project_contacts(t, dt);
      metrics_.timings.projection += projection.microseconds();
    }
  }
}

void Simulation::project_contacts(std::size_t t, Real dt) {
  const std::size_t ni = world_.instruments.size();
  const std::size_t nt = world_.tissues.size();
  TissueBody& tissue = *world_.tissues[t];
  const ProjectedTissue view{tissue.state.positions, tissue.state.velocities, tissue.settings.masses,
                             tissue.settings.fixed, tissue.settings.triangles};
  for (std::size_t i = 0; i < ni; ++i) {
    const InstrumentBody& body = world_.instruments[i];
    const ProjectionStats stats = projectors_[i * nt + t].project(
        body.instrument, fields_[i], contacts_, static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(ni + t),
        solver(i, t).grasp(), view, body.thickness, dt, settings_.response);
    loads_[i].raw_force += stats.force;
    loads_[i].raw_torque += stats.torque;
  }
}

void Simulation::measure() {
  for (const auto& tissue : world_.tissues) {
    metrics_.kinetic_energy += kinetic_energy(tissue->settings, tissue->state.velocities);
    metrics_.elastic_energy += tissue->energy.elastic(tissue->state.positions);
    if (!all_finite(tissue->state.positions) || !all_finite(tissue->state.velocities)) metrics_.finite = false;
    // The fastest speed as √(max |u|²): sqrt is monotonic, so the same bits as max |u|.
    Real speed_squared = 0;
    for (const Vec3& u : tissue->state.velocities) speed_squared = std::max(speed_squared, u.squaredNorm());
    metrics_.max_speed = std::max(metrics_.max_speed, std::sqrt(speed_squared));
  }
  if (!settings_.measure_penetration || !metrics_.finite) return;
  for (std::size_t t = 0; t < world_.tissues.size(); ++t)
    if (distances_[t]) measure_penetration(t);
}

void Simulation::measure_penetration(std::size_t t) {
  const std::size_t ni = world_.instruments.size();
  const std::size_t nt = world_.tissues.size();
  const TissueBody& tissue = *world_.tissues[t];
  const bool sheet = !tissue.settings.closed;
  // A point outside the box of a closed surface's vertices is outside the surface. Near a
  // sheet, the box grows by how far any vertex can have moved this step and the last (the
  // instrument's rigid motion, the fastest tissue vertex) and by the instrument's thickness:
  // a vertex that crossed the sheet is then measured on both sides of it.
  const Aabb tissue_box = Aabb::of_points(tissue.state.positions).inflated(kBoxSlack);
  bool refitted = false;
  start_refitted_ = false;
  for (std::size_t i = 0; i < ni; ++i) {
    const InstrumentBody& body = world_.instruments[i];
    const Instrument& instrument = body.instrument;
    const Real moved = (instrument.linear_velocity().norm() + instrument.angular_velocity().norm() * reach_[i] +
                        metrics_.max_speed) * dt_;
    const Aabb inside_box = sheet ? tissue_box.inflated(2 * moved + body.thickness) : tissue_box;
    // No vertex in the box: all outside, no refit and no query (an instrument on its way in).
    // A vertex through a sheet is measured wherever it is.
    const std::vector<std::uint8_t>& through = through_[i * nt + t];
    const bool any_through = sheet && std::find(through.begin(), through.end(), 1) != through.end();
    if (!any_through && (!inside_box.overlaps(instrument.world_obb().bounds()) ||
                         !any_inside(instrument.world_positions(), inside_box))) {
      std::fill(previous_distance_[i * nt + t].begin(), previous_distance_[i * nt + t].end(),
                sheet ? kUnknown : kOutside);
      continue;
    }
    if (!refitted) {
      // The surface of the last refit, normally this step's start surface, becomes the
      // tunneling check's MeshDistance: most steps with candidates then need no second refit.
      std::swap(distances_[t], start_distances_[t]);
      distances_[t]->refit(tissue.state.positions);
      refitted = true;
    }
    // Instrument vertices of this step's contacts with this tissue (contacts are sorted by
    // object pair, a short run).
    std::vector<std::uint8_t>& touched = touched_[i];
    std::fill(touched.begin(), touched.end(), std::uint8_t{0});
    for (const Contact& c : contacts_) {
      if (c.kind != ContactKind::kInstrumentTissue || c.object_a != i || c.object_b != ni + t) continue;
      for (std::uint32_t v : body.instrument.triangles()[c.triangle_a]) touched[v] = 1;
    }
    // Vertices whose contact the xpbd solver or the sdf projection found itself.
    std::span<const std::uint8_t> hits;
    if (const InstrumentContacts* contacts = solver_contacts_[t].get())
      hits = contacts->hits(i);
    else if (!projectors_.empty())
      hits = projectors_[i * nt + t].instrument_hits();
    for (std::size_t v = 0; v < hits.size() && v < touched.size(); ++v) touched[v] |= hits[v];
    measure_pair(i, t, inside_box, sheet);
  }
}

void Simulation::measure_pair(std::size_t i, std::size_t t, const Aabb& inside_box, bool sheet) {
  const std::size_t nt = world_.tissues.size();
  const InstrumentBody& body = world_.instruments[i];
  std::span<const Vec3> points = body.instrument.world_positions();
  std::vector<Real>& previous = previous_distance_[i * nt + t];
  std::vector<std::uint32_t>& nearest = nearest_triangle_[i * nt + t];
  const auto record = [&](std::uint32_t v, const SignedDistanceResult& r) {
    if (sheet) {
      previous[v] = sheet_side(body, i, t, v, r);
      return;
    }
    if (r.distance < 0) count_inside(body, i, t, v, r.distance);
    previous[v] = r.distance;
  };
  QueryBatch batch;
  const auto flush = [&] {
    const std::size_t n = batch.count;
    distances_[t]->signed_distances(std::span(batch.points).first(n), std::span(batch.hints).first(n),
                                    std::span(batch.results).first(n), query_scratch_);
    for (std::size_t k = 0; k < n; ++k) {
      nearest[batch.vertices[k]] = batch.hints[k];
      record(batch.vertices[k], batch.results[k]);
    }
    batch.count = 0;
  };
  const std::vector<std::uint8_t>& through = through_[i * nt + t];
  for (const std::uint32_t v : query_order_[i]) {
    if (!inside_box.contains(points[v]) && !(sheet && through[v] != 0)) {
      previous[v] = sheet ? kUnknown : kOutside;
      continue;
    }
    batch.points[batch.count] = points[v];
    batch.hints[batch.count] = nearest[v];
    batch.vertices[batch.count] = v;
    if (++batch.count == QueryBatch::kSize) flush();
  }
  if (batch.count > 0) flush();
}

const MeshDistance& Simulation::start_surface(std::size_t t) {
  if (!start_refitted_) {
    // Normally still the previous refit's surface, which is this step's start (simulation.h).
    if (!same_bits(start_distances_[t]->positions(), start_positions_[t]))
      start_distances_[t]->refit(start_positions_[t]);
    start_refitted_ = true;
  }
  return *start_distances_[t];
}

void Simulation::count_inside(const InstrumentBody& body, std::size_t i, std::size_t t, std::uint32_t v, Real d) {
  const std::size_t nt = world_.tissues.size();
  const Real prev = previous_distance_[i * nt + t][v];
  ++metrics_.vertices_inside;
  metrics_.penetration_max = std::max(metrics_.penetration_max, -d);
  bool crossed = false;
  if (prev > 0 && touched_[i][v] == 0) {
    // Did the vertex's own motion carry it across, i.e. is it inside the surface as the
    // detection saw it? Otherwise the tissue moved over it after the response (a
    // spring-back onto the tool, answered by the next detection), not a miss.
    const Vec3& p = body.instrument.world_positions()[v];
    crossed = start_surface(t).signed_distance(p, nearest_triangle_[i * nt + t][v]).distance < 0;
  }
  if (crossed) {
    ++metrics_.tunneling_events;  // (a) crossed the surface with no contact seen
  } else if (-d > body.thickness && !(-prev > body.thickness)) {
    ++metrics_.tunneling_events;  // (b) deeper than the instrument is thick
  }
}

std::uint64_t Simulation::state_hash() const {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const auto& tissue : world_.tissues) {
    for (const Vec3& x : tissue->state.positions) hash_vec(h, x);
    for (const Vec3& v : tissue->state.velocities) hash_vec(h, v);
  }
  for (const InstrumentBody& body : world_.instruments) {
    const Pose& p = body.instrument.pose();
    for (int k = 0; k < 4; ++k) hash_real(h, p.rotation.coeffs()[k]);
    hash_vec(h, p.translation);
    hash_real(h, body.instrument.jaw());
  }
  return h;
}

std::string hash_hex(std::uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace trocar

#include "trocar/sim/simulation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numeric>

#include "trocar/core/timer.h"
#include "trocar/electrosurgery/electrode.h"
#include "trocar/response/xpbd_coupling.h"
#include "trocar/tissue/forces.h"

namespace trocar {
namespace {

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

void hash_vec(std::uint64_t& h, const Vec3& v) {
  for (int k = 0; k < 3; ++k) hash_real(h, v[k]);
}

/// Where an instrument waiting outside the body is kept: far from every scene (a scene is
/// centimetres across), a metre apart from the next one, so it neither touches nor is touched.
Pose parking_pose(std::size_t i) {
  Pose p;
  p.translation = Vec3(0, 0, 100.0 + static_cast<Real>(i));
  return p;
}

}  // namespace

Simulation::Simulation(World world, const SimulationSettings& settings)
    : world_(std::move(world)), settings_(settings), detector_(make_detector(settings)) {
  const std::size_t ni = world_.instruments.size();
  const std::size_t nt = world_.tissues.size();
  commands_.resize(ni);
  // Tissues that enter later wait far from everything (a kilometre out along x, apart from one
  // another and from the instruments parked beyond the ports, which wait along z).
  tissue_waiting_.assign(nt, 0);
  coupled_.assign(nt, CoupledTissue{});
  coupled_stats_.assign(nt, XpbdStats{});
  for (std::size_t t = 0; t < nt; ++t) {
    TissueBody& tissue = *world_.tissues[t];
    if (!(tissue.enters_at > 0)) continue;
    tissue_waiting_[t] = 1;
    const Vec3 away(1000.0 + 10.0 * static_cast<Real>(t), 0, 0);
    for (std::size_t v = 0; v < tissue.state.positions.size(); ++v) {
      tissue.state.positions[v] = tissue.settings.rest_positions[v] + away;
      tissue.state.velocities[v] = Vec3::Zero();
    }
  }
  // Only instrument contacts are answered by the step's responses; tissue against tissue is the
  // tissue contact solver's (with its own search), rigid obstacles are only drawn.
  detector_.set_instrument_pairs_only(true);
  // Ports: instruments naming the same port share one group; the first of a group is inside.
  phase_.assign(ni, PortPhase::kInside);
  port_of_.resize(ni);
  for (std::size_t i = 0; i < ni; ++i) {
    const std::string& port = world_.instruments[i].port;
    std::size_t first = i;
    for (std::size_t j = 0; j < i && first == i; ++j)
      if (!port.empty() && world_.instruments[j].port == port) first = j;
    if (first == i) {
      port_of_[i] = static_cast<std::uint32_t>(port_active_.size());
      port_active_.push_back(i);
    } else {
      port_of_[i] = port_of_[first];
      phase_[i] = PortPhase::kOutside;
    }
  }
  for (std::size_t i = 0; i < ni; ++i) {
    InstrumentBody& body = world_.instruments[i];
    const MotionSample s = body.motion.sample(0);
    body.instrument.reset_pose(phase_[i] == PortPhase::kOutside ? parking_pose(i) : s.pose);
    body.instrument.set_jaw(s.jaw);
  }
  for (const InstrumentBody& body : world_.instruments)
    objects_.push_back({ObjectRole::kInstrument, body.instrument.world_positions(), body.instrument.triangles()});
  for (const auto& tissue : world_.tissues)
    objects_.push_back({ObjectRole::kTissue, tissue->state.positions, tissue->settings.triangles});
  for (const RigidBody& rigid : world_.rigids)
    objects_.push_back({ObjectRole::kRigid, rigid.mesh.positions, rigid.mesh.triangles});

  for (const auto& tissue : world_.tissues)
    if (needs_instrument_field(tissue->integrator.kind(), settings_.response)) {
      for (const InstrumentBody& body : world_.instruments) fields_.emplace_back(body.instrument.local_mesh());
      break;
    }
  std::vector<ResponseInstrument> instruments;
  for (std::size_t i = 0; i < ni; ++i)
    instruments.push_back({&world_.instruments[i].instrument, fields_.empty() ? nullptr : &fields_[i],
                           world_.instruments[i].thickness});
  for (std::size_t t = 0; t < nt; ++t) {
    TissueBody& tissue = *world_.tissues[t];
    const ResponseTissue view{&tissue.settings, &tissue.state, &tissue.loads, &tissue.integrator,
                              static_cast<std::uint32_t>(ni + t)};
    ResponseSettings response = settings_.response;
    if (!tissue.graspable) response.grasp_closure = std::numeric_limits<Real>::infinity();  // jaws never hold it
    responses_.push_back(make_tissue_response(view, instruments, response));
  }
  loads_.resize(ni);
  tissue_forces_.assign(nt * ni, Vec3::Zero());
  for (const auto& tissue : world_.tissues) tissue_masses_.push_back(tissue->settings.total_mass());
  raw_before_.assign(ni, Vec3::Zero());
  instrument_metrics_.resize(ni);
  std::vector<ContactTissue> contact_tissues;
  for (const auto& tissue : world_.tissues) contact_tissues.push_back({&tissue->settings, &tissue->state});
  tissue_contact_ = std::make_unique<TissueContactSolver>(std::move(contact_tissues), settings_.tissue_contacts);
  meter_ = std::make_unique<PenetrationMeter>(world_, settings_.measure_penetration);
  contacts_.reserve(1024);

  // Electrosurgery: each electrode's vertices (from the tip end along the shaft, the tip → top
  // vertex direction), each tissue's thermal state.
  energy_on_.assign(ni, 0);
  suction_on_.assign(ni, 0);
  irrigation_on_.assign(ni, 0);
  electrode_.resize(ni);
  std::size_t most = 0;
  for (std::size_t i = 0; i < ni; ++i) {
    const InstrumentBody& body = world_.instruments[i];
    if (!(body.electrode.power > 0)) continue;
    const TriMesh& mesh = body.instrument.local_mesh();
    if (mesh.positions.empty()) continue;
    Vec3 shaft = mesh.positions[body.instrument.top_vertex()];
    shaft = shaft.norm() > 0 ? Vec3(shaft.normalized()) : Vec3::UnitZ();
    // Points at most half the reach apart: whatever lies within reach of the metal is within reach
    // of a point.
    electrode_[i] = electrode_points(mesh.positions, mesh.triangles, shaft, body.electrode.active_length,
                                     std::max<Real>(0.5 * body.electrode.reach, 1e-4));
    most = std::max(most, electrode_[i].size());
  }
  electrode_points_.reserve(most);
  touches_.resize(ni);
  for (auto& list : touches_) list.reserve(1024);
  vapour_.resize(ni);
  Vec3 up = Vec3::UnitZ();
  for (std::size_t t = 0; t < nt; ++t)
    if (world_.tissues[t]->settings.gravity.norm() > 0) up = -world_.tissues[t]->settings.gravity.normalized();
  for (VapourSource& v : vapour_) v.up = up;
  power_.resize(nt);
  touched_.resize(nt);
  coagulated_.resize(nt);
  stiffened_.resize(nt);
  spring_of_.resize(nt);
  burns_.resize(nt);
  next_remodel_.assign(nt, 0);
  bleeding_index_.assign(nt, -1);
  for (std::size_t t = 0; t < nt; ++t) {
    const TissueBody& tissue = *world_.tissues[t];
    thermal_.emplace_back(tissue.thermal, tissue.settings.triangles, tissue.settings.rest_positions,
                          tissue.settings.rest_areas);
    size_burn(t);
    if (!tissue.bleeds) continue;
    bleeding_index_[t] = static_cast<std::int64_t>(bleeding_.add_tissue(tissue.settings.triangles,
                                                                       tissue.settings.rest_positions));
    bleeding_tissues_.push_back(t);
  }
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

std::size_t Simulation::exchange(std::size_t i) {
  const std::uint32_t group = port_of_[i];
  const std::size_t out = port_active_[group];
  if (phase_[out] != PortPhase::kInside) return out;  // an exchange is under way
  std::size_t in = out;
  for (std::size_t k = 1; k < phase_.size() && in == out; ++k) {
    const std::size_t j = (out + k) % phase_.size();
    if (port_of_[j] == group) in = j;
  }
  if (in == out) return out;
  // What leaves the body leaves with its pedal up and its valves shut.
  energy_on_[out] = suction_on_[out] = irrigation_on_[out] = 0;
  phase_[out] = PortPhase::kWithdrawing;
  phase_[in] = PortPhase::kInserting;
  port_active_[group] = in;
  return in;
}

void Simulation::advance_ports() {
  // An exchange takes two steps: in the first the outgoing instrument stays where it is with its
  // jaws open, so that whatever it held is let go where it is; then it leaves for its parking place and
  // the incoming one takes its pose (at rest), and its port's command if the port is driven.
  for (std::size_t out = 0; out < phase_.size(); ++out) {
    if (phase_[out] != PortPhase::kWithdrawing) continue;
    InstrumentBody& body = world_.instruments[out];
    if (body.instrument.jaw() > 0) {
      body.instrument.reset_pose(body.instrument.pose());  // held still
      body.instrument.set_jaw(0);
      continue;  // lets go this step; leaves at the next
    }
    const std::size_t in = port_active_[port_of_[out]];
    const Pose pose = body.instrument.pose();
    world_.instruments[in].instrument.reset_pose(pose);
    if (commands_[out].active) {
      commands_[in] = commands_[out];
      commands_[in].sample.jaw = 0;
      commands_[out].active = false;
    }
    body.instrument.reset_pose(parking_pose(out));
    phase_[out] = PortPhase::kOutside;
    phase_[in] = PortPhase::kInside;
  }
}

const StepMetrics& Simulation::step(Real dt) {
  const Timer total;
  const StageTimings zero{};
  metrics_ = StepMetrics{};
  metrics_.timings = zero;

  Timer stage;
  time_ += dt;
  dt_ = dt;
  advance_ports();
  admit_tissues();
  for (std::size_t i = 0; i < world_.instruments.size(); ++i) {
    if (phase_[i] != PortPhase::kInside) continue;  // outside, or withdrawing: held where it is
    InstrumentBody& body = world_.instruments[i];
    if (!commands_[i].active && body.motion.empty()) continue;  // no keyframes: stays where it is put
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
  meter_->capture_start();  // the surface this step's detection saw
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

  stage.restart();
  burn(dt);
  metrics_.timings.electrosurgery = stage.microseconds();

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

template <typename Respond>
void Simulation::credit_tissue(std::size_t t, Respond&& respond) {
  const std::size_t n = loads_.size();
  for (std::size_t i = 0; i < n; ++i) raw_before_[i] = loads_[i].raw_force;
  respond();
  for (std::size_t i = 0; i < n; ++i) tissue_forces_[t * n + i] += loads_[i].raw_force - raw_before_[i];
}

void Simulation::respond() {
  for (auto& tissue : world_.tissues) tissue->loads.clear();
  for (InstrumentLoad& load : loads_) load = InstrumentLoad{};
  std::fill(tissue_forces_.begin(), tissue_forces_.end(), Vec3::Zero());
  ResponseTally tally;
  for (std::size_t t = 0; t < responses_.size(); ++t)
    credit_tissue(t, [&] { responses_[t]->before_integration(contacts_, loads_, tally); });
  metrics_.contacts += tally.contacts;
  metrics_.contacts_applied += tally.applied;
}

void Simulation::admit_tissues() {
  for (std::size_t t = 0; t < tissue_waiting_.size(); ++t) {
    TissueBody& tissue = *world_.tissues[t];
    // Due when this step's end reaches its time (within rounding of the sum of the steps).
    if (!tissue_waiting_[t] || time_ + 1e-9 < tissue.enters_at) continue;
    tissue_waiting_[t] = 0;
    std::copy(tissue.settings.rest_positions.begin(), tissue.settings.rest_positions.end(),
              tissue.state.positions.begin());
    std::fill(tissue.state.velocities.begin(), tissue.state.velocities.end(), Vec3::Zero());
  }
}

void Simulation::deform(Real dt) {
  ResponseTally tally;
  tissue_contact_->begin_step();
  // Tissues joined by a contact pair or a tack, all XPBD: stepped in lock-step, their contacts and
  // tacks solved inside the substeps (response/xpbd_coupling.h); otherwise after them.
  int substeps = 0;
  for (std::size_t t = 0; t < world_.tissues.size(); ++t) {
    TissueBody& tissue = *world_.tissues[t];
    XpbdSolver* solver = tissue_waiting_[t] || !settings_.couple_tissues ? nullptr : tissue.integrator.xpbd();
    coupled_[t] = CoupledTissue{solver, &tissue.state, &tissue.loads, tissue.integrator.contacts()};
    if (solver != nullptr) substeps = std::max(substeps, solver->options().substeps);
  }
  const bool coupled = substeps > 0 && tissue_contact_->can_couple(coupled_, tissue_waiting_);
  const auto finish = [&](std::size_t t, const StepStats& stats) {
    TissueBody& tissue = *world_.tissues[t];
    if (yield_home(tissue.settings, tissue.state)) tissue.integrator.home_moved();  // plastic anchors
    metrics_.finite = metrics_.finite && stats.finite;
    metrics_.cg_iterations += static_cast<std::uint32_t>(stats.cg_iterations);
    metrics_.substeps = std::max(metrics_.substeps, static_cast<std::uint32_t>(stats.substeps));
    metrics_.constraint_error = std::max(metrics_.constraint_error, stats.constraint_error);
    credit_tissue(t, [&] { responses_[t]->after_integration(contacts_, dt, loads_, tally); });
  };
  for (std::size_t t = 0; t < world_.tissues.size(); ++t) {
    if (tissue_waiting_[t]) continue;  // outside the body: not stepped
    if (coupled && coupled_[t].solver != nullptr) continue;
    TissueBody& tissue = *world_.tissues[t];
    finish(t, tissue.integrator.step(tissue.state, tissue.loads, dt));
  }
  if (coupled) {
    step_coupled(coupled_, *tissue_contact_, dt, substeps, time_, coupled_stats_);
    for (std::size_t t = 0; t < world_.tissues.size(); ++t) {
      if (coupled_[t].solver == nullptr) continue;
      StepStats stats;
      stats.substeps = substeps;
      stats.constraint_error = coupled_stats_[t].max_strain;
      stats.finite = std::isfinite(coupled_stats_[t].max_strain);
      finish(t, stats);
    }
  } else {
    tissue_contact_->solve(dt, time_);
  }
  metrics_.contacts += tally.contacts;
  metrics_.contacts_applied += tally.applied;
  metrics_.timings.projection = tally.after_us;
}

void Simulation::measure() {
  for (std::size_t t = 0; t < world_.tissues.size(); ++t) {
    TissueBody* tissue = world_.tissues[t].get();
    const Real kinetic = kinetic_energy(tissue->settings, tissue->state.velocities);
    metrics_.kinetic_energy += kinetic;
    if (tissue_masses_[t] > 0)
      metrics_.tissue_rms_speed = std::max(metrics_.tissue_rms_speed, std::sqrt(2 * kinetic / tissue_masses_[t]));
    metrics_.elastic_energy += tissue->energy.elastic(tissue->state.positions);
    if (!all_finite(tissue->state.positions) || !all_finite(tissue->state.velocities)) metrics_.finite = false;
    // The fastest speed as √(max |u|²): sqrt is monotonic, so the same bits as max |u|.
    Real speed_squared = 0;
    for (const Vec3& u : tissue->state.velocities) speed_squared = std::max(speed_squared, u.squaredNorm());
    metrics_.max_speed = std::max(metrics_.max_speed, std::sqrt(speed_squared));
  }
  if (!meter_->enabled() || !metrics_.finite) return;
  const PenetrationReading reading = meter_->measure(contacts_, responses_, metrics_.max_speed, dt_);
  metrics_.penetration_max = reading.penetration_max;
  metrics_.vertices_inside = reading.vertices_inside;
  metrics_.tunneling_events = reading.tunneling_events;
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

Simulation::FastestVertex Simulation::fastest_vertex() const {
  FastestVertex best;
  for (std::size_t t = 0; t < world_.tissues.size(); ++t) {
    const MassSpringState& state = world_.tissues[t]->state;
    for (std::size_t v = 0; v < state.velocities.size(); ++v) {
      Real speed = state.velocities[v].norm();
      if (!std::isfinite(speed)) speed = std::numeric_limits<Real>::infinity();
      if (best.tissue != static_cast<std::size_t>(-1) && !(speed > best.speed)) continue;
      best = {t, static_cast<std::uint32_t>(v), speed, state.positions[v]};
    }
  }
  return best;
}

std::string hash_hex(std::uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace trocar

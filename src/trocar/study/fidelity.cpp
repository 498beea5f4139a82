#include "trocar/study/fidelity.h"

#include <algorithm>
#include <cmath>
#include <deque>

#include "trocar/core/error.h"
#include "trocar/device/scripted_device.h"
#include "trocar/runtime/recording.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"

namespace trocar {
namespace {

/// A device that returns the pose set before each read (the reference's recorded poses).
class FeedDevice final : public Device {
 public:
  explicit FeedDevice(const DeviceSpecs& specs) : specs_(specs) {}
  void feed(const Pose& pose, Real jaw, bool connected) {
    input_.pose = pose;
    input_.jaw = jaw;
    connected_ = connected;
    ++input_.sequence;
  }
  void open() override {}
  void close() override {}
  DeviceStatus read(double, DeviceInput& input) override {
    input = input_;
    return connected_ ? DeviceStatus::kConnected : DeviceStatus::kDisconnected;
  }
  void write(const DeviceOutput&) override {}
  const DeviceSpecs& specs() const override { return specs_; }
  DeviceCounters counters() const override { return {}; }

 private:
  DeviceSpecs specs_;
  DeviceInput input_;
  bool connected_ = true;
};

/// The lock-step reference on a sequence of device poses (world, instrument 0; other
/// instruments follow their motion).
std::vector<Vec3> lockstep_reference(const std::string& text, const std::filesystem::path& dir, double rate_hz,
                                     const std::vector<Pose>& poses, const std::vector<Real>& jaws,
                                     double& device_max_force, std::vector<Vec3>* physics_forces = nullptr) {
  Scene scene = parse_scene(text, "fidelity reference", dir);
  scene.settings.measure_penetration = false;
  const std::vector<DeviceSpec> specs = scene.devices;
  Simulation sim(std::move(scene.world), scene.settings);
  std::vector<RuntimeChannel> channels = make_channels(specs, sim.world());
  FeedDevice feed(channels[0].device->specs());
  device_max_force = std::min(channels[0].shaping.max_force, feed.specs().max_force);
  ForceShaping shaping = channels[0].shaping;
  shaping.max_force = device_max_force;
  PhysicsStepper stepper(sim, RuntimeSettings{}.stiffness_prior);
  ModelHandover once;
  once.blend_ticks = 1;
  HapticChannel channel(feed, DeviceMapping{}, channels[0].coupling, shaping, once);
  const double period = 1.0 / rate_hz;
  InstrumentCommandSet commands;
  StepRecord record;
  TickInstrument tick;
  std::vector<Vec3> forces;
  forces.reserve(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    feed.feed(poses[k], jaws[k], true);
    commands.instruments[0] = channel.sense(double(k) * period);
    const ContactModelSet& m = stepper.step(commands, period, 0, record);
    channel.actuate(m.instruments[0], m.step, 0, period, tick);
    forces.push_back(channel.force());
    if (physics_forces) physics_forces->push_back(m.instruments[0].force0);  // low-passed, as rendered
  }
  return forces;
}

// RMS of the difference of two physics force series (low-passed as the models carry them, each
// clamped to the peak as the devices are), relative to the peak: how far the two runs'
// simulations themselves went apart.
double physics_divergence(const std::vector<Vec3>& a, const std::vector<Vec3>& b, double peak) {
  const std::size_t n = std::min(a.size(), b.size());
  if (n == 0 || !(peak > 0)) return 0;
  const auto clamp = [peak](Vec3 f) { return f.norm() > peak ? Vec3(f * (peak / f.norm())) : f; };
  double sum = 0;
  for (std::size_t k = 0; k < n; ++k) sum += (clamp(a[k]) - clamp(b[k])).squaredNorm();
  return std::sqrt(sum / double(n)) / peak;
}

}  // namespace

FidelityResult compare_forces(const std::vector<Vec3>& rendered, const std::vector<Vec3>& reference,
                              const std::vector<std::uint8_t>& arrivals, double device_max_force) {
  FidelityResult r;
  r.device_max_force = device_max_force;
  const std::size_t n = std::min(rendered.size(), reference.size());
  r.ticks = n;
  double sum = 0;
  for (std::size_t k = 0; k < n; ++k) {
    r.peak_force = std::max(r.peak_force, reference[k].norm());
    sum += (rendered[k] - reference[k]).squaredNorm();
    if (k > 0) {
      r.reference_max_jump = std::max(r.reference_max_jump, (reference[k] - reference[k - 1]).norm());
      const double jump = (rendered[k] - rendered[k - 1]).norm();
      r.max_jump = std::max(r.max_jump, jump);
      if (k < arrivals.size() && arrivals[k]) {
        r.max_arrival_jump = std::max(r.max_arrival_jump, jump);
        ++r.model_arrivals;
      }
    }
  }
  r.rms_error = n ? std::sqrt(sum / double(n)) : 0;
  r.rms_fraction = r.peak_force > 0 ? r.rms_error / r.peak_force : 0;
  return r;
}

FidelityResult emulate_multirate(const std::string& text, const std::filesystem::path& dir,
                                 const EmulationOptions& o) {
  Scene scene = parse_scene(text, "fidelity emulation", dir);
  scene.settings.measure_penetration = false;
  const std::vector<DeviceSpec> specs = scene.devices;
  Simulation sim(std::move(scene.world), scene.settings);
  std::vector<RuntimeChannel> channels = make_channels(specs, sim.world());
  const double period = 1.0 / o.rate_hz;
  PhysicsStepper stepper(sim, RuntimeSettings{}.stiffness_prior);
  ModelHandover handover;
  std::vector<HapticChannel> haptic;
  for (RuntimeChannel& c : channels) {
    check_coupling_passivity(c.coupling, c.device->specs().damping, period, c.where + ".coupling");
    c.shaping.max_force = std::min(c.shaping.max_force, c.device->specs().max_force);
    haptic.emplace_back(*c.device, c.mapping, c.coupling, c.shaping, handover);
  }
  const auto ticks = static_cast<std::size_t>(std::llround(o.duration * o.rate_hz));
  std::deque<std::pair<std::size_t, ContactModelSet>> in_flight;  // (due tick, model) on their way
  ContactModelSet visible;
  InstrumentCommandSet commands;
  StepRecord record;
  TickInstrument tick;
  std::vector<Vec3> rendered;
  std::vector<Pose> poses;
  std::vector<Real> jaws;
  std::vector<std::uint8_t> arrivals;
  for (std::size_t k = 0; k < ticks; ++k) {
    const double now = double(k) * period;
    for (HapticChannel& h : haptic) h.sense(now);
    bool arrived = false;
    while (!in_flight.empty() && in_flight.front().first <= k) {
      visible = in_flight.front().second;
      in_flight.pop_front();
      arrived = true;
    }
    for (std::size_t i = 0; i < haptic.size(); ++i)
      haptic[i].actuate(visible.instruments[i], visible.step, 0, period, tick);
    rendered.push_back(haptic[0].force());
    // The device pose the reference will see this tick: the mapped device pose (recorded).
    poses.push_back(from_words(tick.device_pose));
    jaws.push_back(tick.jaw);
    arrivals.push_back(arrived ? 1 : 0);
    if (k % static_cast<std::size_t>(o.physics_every) == 0) {
      for (std::size_t i = 0; i < haptic.size(); ++i) commands.instruments[i] = haptic[i].command();
      const ContactModelSet& m = stepper.step(commands, period * o.physics_every, 0, record);
      in_flight.emplace_back(k + static_cast<std::size_t>(std::max(1, o.latency_ticks)), m);
    }
  }
  double device_max = 0;
  const std::vector<Vec3> reference = lockstep_reference(text, dir, o.rate_hz, poses, jaws, device_max);
  FidelityResult r = compare_forces(rendered, reference, arrivals, device_max);
  r.physics_rate_hz = o.rate_hz / o.physics_every;
  return r;
}

FidelityResult measure_multirate(const std::filesystem::path& scene_file, double duration, double rate_hz,
                                 const std::filesystem::path& recording) {
  const std::string text = read_scene_text(scene_file);
  {
    Scene scene = parse_scene(text, scene_file.string(), scene_file.parent_path());
    scene.settings.measure_penetration = false;
    const std::vector<DeviceSpec> specs = scene.devices;
    const Real timestep = scene.timestep;
    Simulation sim(std::move(scene.world), scene.settings);
    RuntimeSettings settings;
    settings.haptic_rate_hz = rate_hz;
    settings.duration = duration;
    settings.physics_timestep = timestep;
    RecordingWriter writer(recording, session_header(scene_file, text, sim, settings));
    Runtime runtime(sim, make_channels(specs, sim.world()), settings, &writer);
    runtime.run();
    finish_recording(writer, sim);
  }
  const Recording rec = read_recording(recording, true);
  std::vector<Vec3> rendered;
  std::vector<Pose> poses;
  std::vector<Real> jaws;
  std::vector<std::uint8_t> arrivals;
  std::uint64_t last_model = 0;
  std::vector<Vec3> step_force(rec.steps.size() + 1, Vec3::Zero());  // by step index
  {  // the steps' forces through the physics stepper's low-pass, as its models carry them
    const Real a = rec.header.timestep / (PhysicsStepper::kForceFilter + rec.header.timestep);
    Vec3 filtered = Vec3::Zero();
    for (const StepRecord& st : rec.steps) {
      filtered += a * (Vec3(st.instrument[0].force[0], st.instrument[0].force[1], st.instrument[0].force[2]) - filtered);
      if (st.step < step_force.size()) step_force[st.step] = filtered;
    }
  }
  std::vector<Vec3> physics;  // the force of the step whose model each tick rendered
  for (const TickRecord& t : rec.ticks) {
    const TickInstrument& ti = t.instrument[0];
    rendered.emplace_back(ti.force[0], ti.force[1], ti.force[2]);
    poses.push_back(from_words(ti.device_pose));
    jaws.push_back(ti.jaw);
    arrivals.push_back(ti.model_step != last_model ? 1 : 0);
    last_model = ti.model_step;
    physics.push_back(ti.model_step < step_force.size() ? step_force[ti.model_step] : Vec3::Zero());
  }
  double device_max = 0;
  std::vector<Vec3> reference_physics;
  const std::vector<Vec3> reference =
      lockstep_reference(text, scene_file.parent_path(), rate_hz, poses, jaws, device_max, &reference_physics);
  FidelityResult r = compare_forces(rendered, reference, arrivals, device_max);
  r.physics_rms_fraction = physics_divergence(physics, reference_physics, r.peak_force);
  const double wall = rec.ticks.empty() ? 0 : double(rec.ticks.back().time_ns) * 1e-9;
  r.physics_rate_hz = wall > 0 ? double(rec.steps.size()) / wall : 0;
  return r;
}

}  // namespace trocar

#include "trocar/runtime/session.h"

#include <memory>
#include <vector>

#include "trocar/core/cpu_features.h"
#include "trocar/core/error.h"
#include "trocar/device/null_device.h"
#include "trocar/device/port_device.h"
#include "trocar/device/scripted_device.h"
#include "trocar/procedure/procedure.h"
#include "trocar/runtime/recording.h"
#include "trocar/runtime/replay_device.h"
#ifdef TROCAR_HAVE_OPENIGTLINK
#include "trocar/device/openigtlink_device.h"
#endif
#ifdef TROCAR_HAVE_SPNAV
#include "trocar/device/spacemouse_device.h"
#endif

namespace trocar {

PortKinematics port_kinematics(const DeviceSpec& spec, const InstrumentBody& body) {
  const Pose start = body.motion.keyframes().empty() ? body.instrument.pose() : body.motion.sample(0).pose;
  const Instrument& inst = body.instrument;
  const Vec3 top_local = inst.local_mesh().positions[inst.top_vertex()];
  const Vec3 shaft = start.apply(top_local) - start.translation;
  const Vec3 pivot = spec.has_pivot ? spec.pivot : default_port(start, top_local);
  return PortKinematics(start, shaft.norm() > 1e-9 ? Vec3(shaft.normalized()) : Vec3(0, 0, 1), pivot);
}

namespace {

std::unique_ptr<Device> make_device(const DeviceSpec& spec, const InstrumentBody& body, std::size_t index) {
  if (!spec.given || spec.driver == "scripted") {
    std::vector<ButtonPress> presses;
    for (const DeviceSpec::Press& p : spec.presses) presses.push_back({p.t, p.buttons, p.until});
    return std::make_unique<ScriptedDevice>(body.motion, spec.max_force, spec.damping, std::move(presses));
  }
  if (spec.driver == "mouse") return std::make_unique<PortDevice>(port_kinematics(spec, body));
  if (spec.driver == "null") return std::make_unique<NullDevice>(body.motion.sample(0).pose);
  if (spec.driver == "replay") return std::make_unique<ReplayDevice>(spec.recording, index, spec.max_force, spec.damping);
  if (spec.driver == "openigtlink") {
#ifdef TROCAR_HAVE_OPENIGTLINK
    OpenIgtLinkSettings s;
    s.port = spec.port;
    s.max_force = spec.max_force;
    s.damping = spec.damping;
    s.stale_after_s = spec.stale_after;
    return std::make_unique<OpenIgtLinkDevice>(s);
#else
    throw Error(spec.where + ".driver: this build has no openigtlink driver (install libopenigtlink-dev and rebuild)");
#endif
  }
  if (spec.driver == "spacemouse") {
#ifdef TROCAR_HAVE_SPNAV
    return std::make_unique<SpaceMouseDevice>(SpaceMouseSettings{});
#else
    throw Error(spec.where + ".driver: this build has no spacemouse driver (install libspnav-dev and rebuild)");
#endif
  }
  throw Error(spec.where + ".driver: unknown driver \"" + spec.driver + "\"");
}

}  // namespace

std::vector<RuntimeChannel> make_channels(const std::vector<DeviceSpec>& devices, const World& world) {
  std::vector<RuntimeChannel> channels;
  for (std::size_t i = 0; i < world.instruments.size(); ++i) {
    const DeviceSpec spec = i < devices.size() ? devices[i] : DeviceSpec{};
    RuntimeChannel c;
    c.device = make_device(spec, world.instruments[i], i);
    c.mapping.device_to_world = spec.device_to_world;
    c.mapping.scale = spec.scale;
    c.coupling.stiffness = spec.coupling_stiffness;
    c.coupling.damping = spec.coupling_damping;
    c.shaping.max_force = spec.max_force;
    c.shaping.force_scale = spec.force_scale;
    c.shaping.slew_rate = spec.slew_rate;
    c.shaping.engage_below = spec.engage_below;
    c.shaping.ramp_time = spec.ramp_time;
    c.where = spec.given ? spec.where : "instruments[" + std::to_string(i) + "] (scripted from its motion)";
    channels.push_back(std::move(c));
  }
  return channels;
}

RecordingHeader session_header(const std::filesystem::path& scene_file, std::string scene_text,
                               const Simulation& sim, const RuntimeSettings& settings) {
  RecordingHeader h;
  h.instruments = static_cast<std::uint32_t>(sim.world().instruments.size());
  h.haptic_rate_hz = settings.haptic_rate_hz;
  h.timestep = settings.lockstep ? 1.0 / settings.haptic_rate_hz : settings.physics_timestep;
  h.mode = settings.lockstep ? 1 : 0;
  h.kernel_path = kernel_path_name(kernel_path());
  h.scene_path = std::filesystem::absolute(scene_file).lexically_normal().string();
  h.scene_text = std::move(scene_text);
  return h;
}

void finish_recording(RecordingWriter& writer, const Simulation& sim) {
  EndRecord end;
  end.state_hash = sim.state_hash();
  writer.finish(end);
}

ReplayResult replay_recording(const std::filesystem::path& file, ReplayObserver* observer) {
  const Recording rec = read_recording(file, true);
  const std::filesystem::path scene_path(rec.header.scene_path);
  Scene scene = parse_scene(rec.header.scene_text, file.string() + " (scene " + scene_path.string() + ")",
                            scene_path.parent_path());
  SimulationSettings settings = scene.settings;
  settings.measure_penetration = false;  // metrics never change the state
  if (scene.world.instruments.size() != rec.header.instruments)
    throw FileError(file.string(), FileLocation::none(),
                    "the recorded scene has " + std::to_string(scene.world.instruments.size()) +
                        " instruments, the records " + std::to_string(rec.header.instruments));
  Simulation sim(std::move(scene.world), settings);
  // The scene's task fires the tacker on a recorded fire press, as it did live (Runtime::set_procedure).
  std::unique_ptr<Procedure> procedure;
  if (scene.task) procedure = std::make_unique<Procedure>(*scene.task, sim.world(), scene.zones, scene.landmarks);
  ReplayResult r;
  if (observer) observer->start(scene, sim, procedure.get());
  for (const StepRecord& s : rec.steps) {
    apply_recorded_step(sim, s, procedure.get());
    if (procedure) procedure->update(sim);
    if (observer) observer->step(sim, procedure.get(), s);
  }
  if (observer) observer->end(sim, procedure.get());
  r.steps = rec.steps.size();
  r.state_hash = sim.state_hash();
  r.recorded_hash = rec.end->state_hash;
  r.recorded_kernel_path = rec.header.kernel_path;
  r.kernel_path = kernel_path_name(kernel_path());
  return r;
}

std::string ReplayResult::verdict() const {
  if (!comparable())
    return "recorded on " + recorded_kernel_path + ", replaying on " + kernel_path +
           ": hashes are not comparable across kernel paths";
  if (matches()) return "identical";
  if (recorded_kernel_path == kUnknownKernelPath)
    return "DIFFERENT (the recording does not state its kernel path; replaying on " + kernel_path +
           ", and a recording made on another path differs)";
  return "DIFFERENT";
}

}  // namespace trocar

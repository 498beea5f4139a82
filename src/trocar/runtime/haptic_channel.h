#pragma once
/// One instrument's haptic path, run every haptic tick: device → world pose (sent to physics) →
/// force from the local contact model through the virtual coupling → device. Allocation-, lock- and
/// exception-free; the Device's read() and write() must be too.
#include <cstdint>

#include "trocar/core/pose.h"
#include "trocar/device/device.h"
#include "trocar/runtime/coupling.h"
#include "trocar/runtime/local_contact_model.h"
#include "trocar/runtime/recording_format.h"

namespace trocar {

/// Where the device's frame sits in the world, and its motion scale.
struct DeviceMapping {
  Pose device_to_world;  ///< world = device_to_world ∘ (scale · device position), rotation composed
  Real scale = 1;        ///< device metres → world metres (motion scaling)

  /// The device pose in the world.
  Pose to_world(const Pose& device) const;
};

/// How the haptic tick treats the models physics hands over.
struct ModelHandover {
  int blend_ticks = 8;          ///< a new model is blended in linearly over this many ticks (1 = at once)
  Real stale_after = 0.010;     ///< s: a model older than this starts fading the force …
  Real fade_time = 0.005;       ///< s: … to zero over this long
};

/// What the physics step should do with this instrument (published by the haptic tick).
struct InstrumentCommand {
  Pose pose;           ///< the device's pose in the world, where physics puts the instrument
  Real jaw = 0;        ///< 0…1
  bool active = false; ///< a sample has arrived (before: the instrument stays where the scene put it)
  /// Action bits held down now (procedure/actions.h): the device's button 1 fires, button 2
  /// exchanges (button 0 closes the jaws); the viewer's keys set them too.
  std::uint32_t actions = 0;
};

/// The haptic path of one instrument.
class HapticChannel {
 public:
  HapticChannel(Device& device, const DeviceMapping& mapping, const CouplingSettings& coupling,
                const ForceShaping& shaping, const ModelHandover& handover);

  /// Reads the device (at now_s since the start); returns the command for physics.
  const InstrumentCommand& sense(double now_s);
  /// Takes `model` (published at physics step `model_step`, `model_age_s` old), computes the
  /// force, shapes it, writes it to the device, and fills `record`.
  void actuate(const LocalContactModel& model, std::uint64_t model_step, double model_age_s, double period_s,
               TickInstrument& record);

  const InstrumentCommand& command() const { return command_; }  ///< after actuate()
  const Vec3& force() const { return force_; }                   ///< sent last tick (N, world)
  std::uint64_t disconnects() const { return disconnects_; }     ///< connected → not, so far

 private:
  /// The current model's force at device position x and velocity v, with the coupling's damper.
  Vec3 model_force(const Vec3& x, const Vec3& v) const;
  /// model_force with the jump of the last model change spread over blend_ticks (the damper
  /// switching on or off with the contact is spread too).
  Vec3 blended_force(const Vec3& x, const Vec3& v) const;

  Device& device_;
  DeviceMapping mapping_;
  CouplingSettings coupling_;
  ForceShaper shaper_;
  ModelHandover handover_;
  DeviceInput input_;
  DeviceStatus status_ = DeviceStatus::kDisconnected;
  Pose device_world_;                 ///< last good device pose (held when the device drops)
  Vec3 device_velocity_ = Vec3::Zero();
  LocalContactModel current_;         ///< newest model
  Vec3 force_offset_ = Vec3::Zero();  ///< rendered − new model's force when it arrived (N)
  Vec3 last_device_ = Vec3::Zero();   ///< device position of the last rendered tick (m)
  Vec3 last_velocity_ = Vec3::Zero(); ///< device velocity of the last rendered tick (m/s)
  Vec3 last_contact_force_ = Vec3::Zero();  ///< contact force of the last rendered tick (N)
  bool have_last_ = false;            ///< last_* hold a rendered tick
  std::uint64_t model_step_ = 0;
  int blend_tick_ = 0;                ///< ticks since current_ arrived
  InstrumentCommand command_;
  Vec3 force_ = Vec3::Zero();
  std::uint64_t disconnects_ = 0;
};

/// Writes a pose as quaternion w, x, y, z and translation (recording_format.h).
PoseWords to_words(const Pose& p);
/// Reads it back (the quaternion as stored, not renormalised: replay must be bit for bit).
Pose from_words(const PoseWords& w);

}  // namespace trocar

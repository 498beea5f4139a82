#include "trocar/runtime/haptic_channel.h"

#include "trocar/procedure/actions.h"

#include <algorithm>

namespace trocar {

Pose DeviceMapping::to_world(const Pose& device) const {
  Pose scaled = device;
  scaled.translation *= scale;
  return device_to_world * scaled;
}

PoseWords to_words(const Pose& p) {
  return {p.rotation.w(), p.rotation.x(), p.rotation.y(), p.rotation.z(),
          p.translation.x(), p.translation.y(), p.translation.z()};
}

Pose from_words(const PoseWords& w) {
  Pose p;
  p.rotation = Quat(w[0], w[1], w[2], w[3]);
  p.translation = Vec3(w[4], w[5], w[6]);
  return p;
}

HapticChannel::HapticChannel(Device& device, const DeviceMapping& mapping, const CouplingSettings& coupling,
                             const ForceShaping& shaping, const ModelHandover& handover)
    : device_(device), mapping_(mapping), coupling_(coupling), shaper_(shaping), handover_(handover) {}

Vec3 HapticChannel::model_force(const Vec3& x, const Vec3& v) const {
  Vec3 f = coupled_force(current_, coupling_.stiffness, x);
  // The coupling's damper, along the contact normal while in contact: resists the device's
  // approach and withdrawal (B of the passivity bound).
  if (f.squaredNorm() > 0) f -= coupling_.damping * current_.normal * current_.normal.dot(v);
  return f;
}

Vec3 HapticChannel::blended_force(const Vec3& x, const Vec3& v) const {
  const Vec3 now = model_force(x, v);
  if (blend_tick_ + 1 >= handover_.blend_ticks) return now;
  // The jump a new model would make is spread over blend_ticks ticks: the offset between the
  // force rendered just before the model arrived and the new model's there, decaying linearly.
  // Continuous however often models arrive (a new one restarts the ramp from where it is).
  const Real a = Real(blend_tick_ + 1) / Real(handover_.blend_ticks);
  return now + (1 - a) * force_offset_;
}

const InstrumentCommand& HapticChannel::sense(double now_s) {
  const DeviceStatus was = status_;
  status_ = device_.read(now_s, input_);
  if (status_ == DeviceStatus::kConnected && input_.sequence > 0) {
    device_world_ = mapping_.to_world(input_.pose);
    device_velocity_ = mapping_.device_to_world.apply_vector(input_.velocity) * mapping_.scale;
    command_.pose = device_world_;
    command_.jaw = input_.jaw;
    command_.actions = (input_.buttons >> 1) & kButtonActions;
    command_.active = true;
  } else {
    // Dropped or silent: the instrument holds its last pose (command_ unchanged).
    device_velocity_ = Vec3::Zero();
    if (was == DeviceStatus::kConnected) ++disconnects_;
  }
  return command_;
}

void HapticChannel::actuate(const LocalContactModel& model, std::uint64_t model_step, double model_age_s,
                            double period_s, TickInstrument& record) {
  if (model_step != model_step_) {
    current_ = model;
    model_step_ = model_step;
    blend_tick_ = 0;
    force_offset_ = have_last_ ? Vec3(last_contact_force_ - model_force(last_device_, last_velocity_)) : Vec3::Zero();
  }
  const bool live = status_ == DeviceStatus::kConnected && command_.active;
  if (live) {
    const Vec3& x = device_world_.translation;
    Vec3 commanded = blended_force(x, device_velocity_);
    last_contact_force_ = commanded;
    last_device_ = x;
    last_velocity_ = device_velocity_;
    have_last_ = true;
    // A model older than stale_after fades out over fade_time (physics stalled).
    if (model_age_s > handover_.stale_after) {
      const double keep = handover_.fade_time > 0 ? 1 - (model_age_s - handover_.stale_after) / handover_.fade_time : 0;
      commanded *= std::clamp(keep, 0.0, 1.0);
    }
    force_ = shaper_.shape(commanded, period_s);
  } else {
    shaper_.disengage();  // zero now; the safe start again on reconnect
    force_ = Vec3::Zero();
    have_last_ = false;
  }
  ++blend_tick_;

  DeviceOutput out;
  out.force = mapping_.device_to_world.rotation.conjugate() * force_;
  out.timestamp_ns = input_.timestamp_ns;
  device_.write(out);

  record.device_pose = to_words(device_world_);
  record.proxy_pose = to_words(command_.pose);
  record.force = {force_.x(), force_.y(), force_.z()};
  record.jaw = command_.jaw;
  record.status = static_cast<std::uint32_t>(status_);
  record.engaged = shaper_.engaged() ? 1U : 0U;
  record.model_step = model_step_;
}

}  // namespace trocar

#include "trocar/core/motion.h"

#include <algorithm>

namespace trocar {

KeyframeMotion::KeyframeMotion(std::vector<Keyframe> keyframes) : keyframes_(std::move(keyframes)) {
  std::stable_sort(keyframes_.begin(), keyframes_.end(), [](const Keyframe& a, const Keyframe& b) { return a.t < b.t; });
  for (Keyframe& k : keyframes_) k.rotation.normalize();
}

MotionSample KeyframeMotion::sample(Real t) const {
  MotionSample out;
  if (keyframes_.empty()) return out;
  const Keyframe* a = &keyframes_.front();
  const Keyframe* b = a;
  if (t <= keyframes_.front().t) {
    b = a;
  } else if (t >= keyframes_.back().t) {
    a = b = &keyframes_.back();
  } else {
    // First keyframe with k.t > t; its predecessor has k.t <= t.
    const auto it = std::upper_bound(keyframes_.begin(), keyframes_.end(), t,
                                     [](Real v, const Keyframe& k) { return v < k.t; });
    b = &*it;
    a = &*(it - 1);
  }
  const Real span = b->t - a->t;
  const Real s = span > 0 ? std::clamp((t - a->t) / span, Real{0}, Real{1}) : Real{0};
  out.pose.translation = a->position + s * (b->position - a->position);
  out.pose.rotation = a->rotation.slerp(s, b->rotation);  // Eigen takes the shorter arc
  out.jaw = a->jaw + s * (b->jaw - a->jaw);
  return out;
}

}  // namespace trocar

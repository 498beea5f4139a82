#include "trocar/core/motion.h"

#include <algorithm>

namespace trocar {

KeyframeMotion::KeyframeMotion(std::vector<Keyframe> keyframes, Interpolation interpolation)
    : keyframes_(std::move(keyframes)), interpolation_(interpolation) {
  std::stable_sort(keyframes_.begin(), keyframes_.end(), [](const Keyframe& a, const Keyframe& b) { return a.t < b.t; });
  for (Keyframe& k : keyframes_) k.rotation.normalize();
  if (interpolation_ != Interpolation::kSmooth) return;
  // The velocity at each keyframe: the time-weighted mean of the two segments' velocities (the
  // three-point derivative on uneven steps), zero at the ends and beside a hold (the hand starts
  // and stops at rest), and at most 3 times the slower segment's speed, the Fritsch–Carlson bound
  // under which a cubic does not overshoot its keyframe along a straight run (Fritsch & Carlson
  // 1980, SIAM J. Numer. Anal. 17:238): a tip that stops at tissue stops there, not beyond it.
  const std::size_t n = keyframes_.size();
  tangents_.assign(n, Vec3::Zero());
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const Real before = keyframes_[k].t - keyframes_[k - 1].t, after = keyframes_[k + 1].t - keyframes_[k].t;
    if (!(before > 0) || !(after > 0)) continue;
    const Vec3 v0 = (keyframes_[k].position - keyframes_[k - 1].position) / before;
    const Vec3 v1 = (keyframes_[k + 1].position - keyframes_[k].position) / after;
    const Real slower = std::min(v0.norm(), v1.norm());
    if (!(slower > 0)) continue;
    Vec3 m = (after * v0 + before * v1) / (before + after);
    if (m.norm() > 3 * slower) m *= 3 * slower / m.norm();
    // Keyframes microseconds apart and metres away: a velocity beyond double's range stays out.
    if (!(m * std::max(before, after)).allFinite()) continue;
    tangents_[k] = m;
  }
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
  if (interpolation_ == Interpolation::kSmooth && span > 0) {
    // Cubic Hermite basis (h00, h10, h01, h11) on the segment, tangents scaled by its length.
    const Real s2 = s * s, s3 = s2 * s;
    const std::size_t i = static_cast<std::size_t>(a - keyframes_.data());
    out.pose.translation = (2 * s3 - 3 * s2 + 1) * a->position + (s3 - 2 * s2 + s) * span * tangents_[i] +
                           (-2 * s3 + 3 * s2) * b->position + (s3 - s2) * span * tangents_[i + 1];
  } else {
    out.pose.translation = a->position + s * (b->position - a->position);
  }
  out.pose.rotation = a->rotation.slerp(s, b->rotation);  // Eigen takes the shorter arc
  out.jaw = a->jaw + s * (b->jaw - a->jaw);
  return out;
}

}  // namespace trocar

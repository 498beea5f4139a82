// Motion metrics of a tip trajectory (docs/assessment.md, "Motion").
#include "trocar/assessment/motion.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace trocar {
namespace {

bool is_present(std::span<const std::uint8_t> present, std::size_t k) { return present.empty() || present[k] != 0; }

}  // namespace

Real path_length(std::span<const Vec3> tip, std::span<const std::uint8_t> present) {
  Real sum = 0;
  for (std::size_t k = 0; k + 1 < tip.size(); ++k)
    if (is_present(present, k) && is_present(present, k + 1)) sum += (tip[k + 1] - tip[k]).norm();
  return sum;
}

Real depth_path(std::span<const Vec3> tip, std::span<const Vec3> axis, std::span<const std::uint8_t> present) {
  Real sum = 0;
  for (std::size_t k = 0; k + 1 < tip.size() && k < axis.size(); ++k)
    if (is_present(present, k) && is_present(present, k + 1)) sum += std::abs((tip[k + 1] - tip[k]).dot(axis[k]));
  return sum;
}

void tip_speeds(std::span<const Vec3> tip, Real dt, std::span<Real> speed, std::span<const std::uint8_t> present) {
  const std::size_t n = std::min(tip.size(), speed.size());
  for (std::size_t k = 0; k < n; ++k) {
    if (!is_present(present, k) || n < 2 || !(dt > 0)) {
      speed[k] = 0;
      continue;
    }
    // Central where both neighbours are present, else one-sided toward the present one.
    const bool back = k > 0 && is_present(present, k - 1);
    const bool ahead = k + 1 < n && is_present(present, k + 1);
    if (back && ahead) speed[k] = (tip[k + 1] - tip[k - 1]).norm() / (2 * dt);
    else if (ahead) speed[k] = (tip[k + 1] - tip[k]).norm() / dt;
    else if (back) speed[k] = (tip[k] - tip[k - 1]).norm() / dt;
    else speed[k] = 0;
  }
}

Real idle_time(std::span<const Real> speed, Real dt, Real threshold, std::span<const std::uint8_t> present) {
  Real idle = 0;
  for (std::size_t k = 0; k < speed.size(); ++k)
    if (is_present(present, k) && speed[k] < threshold) idle += dt;
  return idle;
}

Real log_dimensionless_jerk(std::span<const Vec3> tip, Real dt, std::size_t stride) {
  stride = std::max<std::size_t>(stride, 1);
  std::vector<Vec3> p;
  for (std::size_t k = 0; k < tip.size(); k += stride) p.push_back(tip[k]);
  const Real h = dt * static_cast<Real>(stride);
  if (p.size() < 6 || !(h > 0)) return 0;
  // Velocity at the samples (central inside, second-order one-sided at the ends) and its second
  // derivative by central differences where they use central velocities only (samples 2 … n−3);
  // the two samples at each end extrapolate it linearly (a one-sided difference there errs by the
  // jerk itself). The trapezoid rule covers the whole movement: leaving out the ends would drop
  // about 10h/T of a minimum-jerk reach's integral.
  const std::size_t n = p.size();
  std::vector<Vec3> v(n);
  v[0] = (-3 * p[0] + 4 * p[1] - p[2]) / (2 * h);
  v[n - 1] = (3 * p[n - 1] - 4 * p[n - 2] + p[n - 3]) / (2 * h);
  for (std::size_t k = 1; k + 1 < n; ++k) v[k] = (p[k + 1] - p[k - 1]) / (2 * h);
  Real peak = 0;
  for (const Vec3& x : v) peak = std::max(peak, x.norm());
  if (!(peak > 0)) return 0;
  const auto central = [&](std::size_t c) -> Vec3 { return (v[c + 1] - 2 * v[c] + v[c - 1]) / (h * h); };
  const auto second = [&](std::size_t k) -> Real {
    if (k < 2) return (central(2) - static_cast<Real>(2 - k) * (central(3) - central(2))).squaredNorm();
    if (k > n - 3) return (central(n - 3) + static_cast<Real>(k - (n - 3)) * (central(n - 3) - central(n - 4))).squaredNorm();
    return central(k).squaredNorm();
  };
  Real integral = 0;
  for (std::size_t k = 0; k + 1 < n; ++k) integral += 0.5 * (second(k) + second(k + 1)) * h;
  const Real duration = h * static_cast<Real>(n - 1);
  const Real dimensionless = std::pow(duration, 3) / (peak * peak) * integral;
  if (!(dimensionless > 0)) return 0;
  return -std::log(dimensionless);
}

Real out_of_view_time(std::span<const std::uint8_t> present, std::span<const std::uint8_t> in_view, Real dt) {
  Real t = 0;
  for (std::size_t k = 0; k < present.size() && k < in_view.size(); ++k)
    if (present[k] && !in_view[k]) t += dt;
  return t;
}

}  // namespace trocar

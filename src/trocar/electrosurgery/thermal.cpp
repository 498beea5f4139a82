#include "trocar/electrosurgery/thermal.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace trocar {

Real damage_rate(const ThermalProperties& p, Real temperature) {
  return p.arrhenius_rate * std::exp(-p.activation_energy / (kGasConstant * temperature));
}

ThermalField::ThermalField(const ThermalProperties& properties, std::span<const Triangle> triangles,
                           std::span<const Vec3> rest_positions, std::span<const Real> rest_areas)
    : properties_(properties) {
  const std::size_t n = triangles.size();
  temperature_.assign(n, properties.body_temperature);
  damage_.assign(n, 0.0);
  vaporised_.assign(n, 0.0);
  build(triangles, rest_positions, rest_areas);
}

void ThermalField::build(std::span<const Triangle> triangles, std::span<const Vec3> rest_positions,
                         std::span<const Real> rest_areas) {
  build_capacity(rest_areas);
  build_conduction(triangles, rest_positions);
}

void ThermalField::build_capacity(std::span<const Real> rest_areas) {
  const std::size_t n = rest_areas.size();
  capacity_.resize(n);
  vapour_energy_.resize(n);
  heat_.assign(n, 0.0);
  for (std::size_t t = 0; t < n; ++t) {
    const Real mass = properties_.density * rest_areas[t] * properties_.heated_depth;
    capacity_[t] = mass * properties_.specific_heat;
    vapour_energy_[t] = mass * properties_.water_fraction * properties_.latent_heat;
  }
}

void ThermalField::update_max_rate() {
  std::vector<Real> sum(capacity_.size(), 0.0);
  for (const Link& l : links_) {
    sum[l.a] += l.conductance;
    sum[l.b] += l.conductance;
  }
  max_rate_ = 0;
  for (std::size_t t = 0; t < sum.size(); ++t)
    if (capacity_[t] > 0) max_rate_ = std::max(max_rate_, sum[t] / capacity_[t]);
}

void ThermalField::build_conduction(std::span<const Triangle> triangles, std::span<const Vec3> rest_positions) {
  // Edge → the first triangle seen on it; the second one makes a link.
  links_.clear();
  std::unordered_map<std::uint64_t, std::uint32_t> first;
  first.reserve(3 * triangles.size());
  auto centroid = [&](const Triangle& t) {
    return (rest_positions[t[0]] + rest_positions[t[1]] + rest_positions[t[2]]) / 3.0;
  };
  for (std::uint32_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = triangles[t][k], b = triangles[t][(k + 1) % 3];
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      const auto [it, inserted] = first.try_emplace(key, t);
      if (inserted) continue;
      const std::uint32_t other = it->second;
      const Real edge = (rest_positions[a] - rest_positions[b]).norm();
      const Real apart = (centroid(triangles[t]) - centroid(triangles[other])).norm();
      if (!(apart > 0) || !(edge > 0)) continue;
      links_.push_back({other, t, properties_.conductivity * properties_.heated_depth * edge / apart});
    }
  update_max_rate();
}

void ThermalField::step(std::span<const Real> power, Real dt) {
  bool powered = false;
  for (Real p : power) powered |= p > 0;
  if (!powered && !hot_) return;
  const ThermalProperties& p = properties_;
  // β = w_b c_b / (ρ c): the perfusion's cooling rate (1/s).
  const Real beta = p.perfusion * p.blood_specific_heat / (p.density * p.specific_heat);
  const int substeps = std::max(1, static_cast<int>(std::ceil(dt * max_rate_ / 0.5)));
  const Real h = dt / substeps;
  const std::size_t n = temperature_.size();
  Real hottest = p.body_temperature;
  for (int s = 0; s < substeps; ++s) {
    for (std::size_t t = 0; t < n; ++t) {
      const Real in = power.empty() ? 0.0 : power[t] * h;
      const Real out = capacity_[t] * beta * (temperature_[t] - p.body_temperature) * h;
      heat_[t] = in - out;
      delivered_ += in;
      perfused_ += out;
    }
    for (const Link& l : links_) {
      const Real q = l.conductance * (temperature_[l.b] - temperature_[l.a]) * h;
      heat_[l.a] += q;
      heat_[l.b] -= q;
    }
    hottest = p.body_temperature;
    for (std::size_t t = 0; t < n; ++t) {
      const Real t0 = temperature_[t];
      Real t1 = capacity_[t] > 0 ? t0 + heat_[t] / capacity_[t] : t0;
      if (t1 > p.boiling_temperature) {
        // Up to the boiling point the heat warms; beyond it, it boils the water off.
        const Real excess = (t1 - p.boiling_temperature) * capacity_[t];
        t1 = p.boiling_temperature;
        if (vapour_energy_[t] > 0) vaporised_[t] += excess / vapour_energy_[t];
      }
      temperature_[t] = t1;
      if (t0 > p.body_temperature + 1.0 || t1 > p.body_temperature + 1.0) {
        // Simpson's rule over the substep's linear T(t); below 38 °C the rate is < 1e-7 /s.
        damage_[t] += h / 6.0 * (damage_rate(p, t0) + 4.0 * damage_rate(p, 0.5 * (t0 + t1)) + damage_rate(p, t1));
      }
      hottest = std::max(hottest, t1);
    }
  }
  hot_ = hottest > p.body_temperature + 0.01;
}

void ThermalField::add_heat(std::size_t t, Real joules) {
  if (t >= temperature_.size() || !(joules > 0) || !(capacity_[t] > 0)) return;
  delivered_ += joules;
  Real t1 = temperature_[t] + joules / capacity_[t];
  if (t1 > properties_.boiling_temperature) {
    if (vapour_energy_[t] > 0) vaporised_[t] += (t1 - properties_.boiling_temperature) * capacity_[t] / vapour_energy_[t];
    t1 = properties_.boiling_temperature;
  }
  temperature_[t] = t1;
  hot_ = true;
}

void ThermalField::remap(std::span<const std::uint32_t> origin, std::span<const Triangle> triangles,
                         std::span<const Vec3> rest_positions, std::span<const Real> rest_areas) {
  const std::size_t n = origin.size(), old_n = temperature_.size();
  constexpr std::uint32_t kNone = ~std::uint32_t{0};
  std::vector<std::uint32_t> now(old_n, kNone);  // old triangle → new (kNone: removed)
  bool one_to_one = true;
  std::vector<Real> temperature(n), damage(n), vaporised(n);
  for (std::size_t k = 0; k < n; ++k) {
    temperature[k] = temperature_[origin[k]];
    damage[k] = damage_[origin[k]];
    vaporised[k] = vaporised_[origin[k]];
    if (now[origin[k]] != kNone) one_to_one = false;
    now[origin[k]] = static_cast<std::uint32_t>(k);
  }
  temperature_ = std::move(temperature);
  damage_ = std::move(damage);
  vaporised_ = std::move(vaporised);
  if (!one_to_one) {
    build(triangles, rest_positions, rest_areas);
    return;
  }
  build_capacity(rest_areas);
  std::size_t kept = 0;
  for (const Link& l : links_)
    if (now[l.a] != kNone && now[l.b] != kNone) links_[kept++] = {now[l.a], now[l.b], l.conductance};
  links_.resize(kept);
  update_max_rate();
}

Real ThermalField::stored() const {
  Real sum = 0;
  for (std::size_t t = 0; t < temperature_.size(); ++t)
    sum += capacity_[t] * (temperature_[t] - properties_.body_temperature);
  return sum;
}

Real ThermalField::latent() const {
  Real sum = 0;
  for (std::size_t t = 0; t < vaporised_.size(); ++t) sum += vaporised_[t] * vapour_energy_[t];
  return sum;
}

}  // namespace trocar

// The electrodes' heat and the tissues' thermal damage in the step (docs/electrosurgery.md).
#include <algorithm>
#include <limits>

#include "trocar/core/timer.h"
#include "trocar/electrosurgery/electrode.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

/// The index of the point of `points` (not empty) nearest p.
std::uint32_t nearest_vertex(std::span<const Vec3> points, const Vec3& p) {
  std::uint32_t nearest = 0;
  Real best = std::numeric_limits<Real>::infinity();
  for (std::uint32_t v = 0; v < points.size(); ++v) {
    const Real d = (points[v] - p).squaredNorm();
    if (d < best) {
      best = d;
      nearest = v;
    }
  }
  return nearest;
}

}  // namespace

void Simulation::size_burn(std::size_t t) {
  const TissueBody& tissue = *world_.tissues[t];
  const std::size_t n = tissue.settings.triangles.size();
  power_[t].assign(n, 0.0);
  touched_[t].assign(n, 0);
  coagulated_[t].resize(n, 0);
  stiffened_[t].resize(tissue.settings.springs.size(), 0);
  spring_of_[t].clear();
  // A remodel's scratch holds any tissue's triangles and their edges without growing.
  remodel_cut_.reserve(n);
  remodel_coagulating_.reserve(n);
  remodel_changed_.reserve(3 * n);
  remodel_before_.reserve(3 * n);
}

BurnTally Simulation::burn_tally(std::size_t t) const {
  BurnTally tally = burns_[t];
  const MassSpringSettings& s = world_.tissues[t]->settings;
  const ThermalField& field = thermal_[t];
  tally.energy = field.delivered();
  for (std::size_t k = 0; k < field.size(); ++k)
    if (field.coagulated(k)) tally.coagulated_area += s.rest_areas[k];
  return tally;
}

void Simulation::cut(std::size_t t, std::span<const std::uint32_t> triangles) {
  if (t >= thermal_.size()) return;
  bool any = false;
  for (const std::uint32_t k : triangles)
    if (k < thermal_[t].size()) {
      thermal_[t].vaporise(k);
      any = true;
    }
  if (any) remodel(t);
}

void Simulation::heat(std::size_t t, std::uint32_t k, Real joules) {
  if (t < thermal_.size()) thermal_[t].add_heat(k, joules);
}

void Simulation::burn(Real dt) {
  const std::size_t nt = world_.tissues.size();
  bool any = false;
  for (VapourSource& v : vapour_) v.burning = false;
  for (std::size_t i = 0; i < world_.instruments.size(); ++i) {
    const InstrumentBody& body = world_.instruments[i];
    if (!energy_on_[i] || !(body.electrode.power > 0) || phase_[i] != PortPhase::kInside || electrode_[i].empty())
      continue;
    const Pose& pose = body.instrument.pose();
    electrode_points_.clear();
    for (const Vec3& p : electrode_[i]) electrode_points_.push_back(pose.apply(p));
    // The touched area over every tissue first: the power is shared over all of it.
    Real area = 0;
    for (std::size_t t = 0; t < nt; ++t) {
      if (tissue_waiting_[t]) continue;
      const TissueBody& tissue = *world_.tissues[t];
      area += touch_triangles(electrode_points_, tissue.state.positions, tissue.settings.triangles,
                              tissue.settings.rest_areas, body.electrode.reach, touched_[t]);
    }
    if (!(area > 0)) continue;
    any = true;
    // The shares, and where they go (the touched surface's centre, area-weighted: smoke's source).
    Vec3 centre = Vec3::Zero();
    for (std::size_t t = 0; t < nt; ++t) {
      if (tissue_waiting_[t]) continue;
      const TissueBody& tissue = *world_.tissues[t];
      share_power(body.electrode.power, area, touched_[t], tissue.settings.rest_areas, power_[t]);
      for (std::uint32_t k = 0; k < touched_[t].size(); ++k) {
        if (!touched_[t][k]) continue;
        const Real share = body.electrode.power * tissue.settings.rest_areas[k] / area;
        const Triangle& tri = tissue.settings.triangles[k];
        centre += tissue.settings.rest_areas[k] *
                  (tissue.state.positions[tri[0]] + tissue.state.positions[tri[1]] + tissue.state.positions[tri[2]]) / 3;
        if (touches_[i].size() < touches_[i].capacity())
          touches_[i].push_back({static_cast<std::uint32_t>(t), k, share});
      }
    }
    vapour_[i].at = centre / area;
    vapour_[i].burning = true;
    metrics_.energy += body.electrode.power * dt;
  }
  for (std::size_t t = 0; t < nt; ++t) {
    if (tissue_waiting_[t]) continue;
    if (any || thermal_[t].hot()) thermal_[t].step(any ? std::span<const Real>(power_[t]) : std::span<const Real>(), dt);
    if (any) std::fill(power_[t].begin(), power_[t].end(), 0.0);
  }
  // At the boiling point the heat boils water off: that share of each electrode's power is vapour.
  for (std::size_t i = 0; i < touches_.size(); ++i) {
    for (const Touch& touch : touches_[i]) {
      const ThermalField& field = thermal_[touch.tissue];
      if (field.temperature()[touch.triangle] >= field.properties().boiling_temperature)
        vapour_[i].energy += touch.watts * dt;
    }
    touches_[i].clear();
  }
  for (std::size_t t = 0; t < nt; ++t)
    if (thermal_[t].hot() && time_ + 1e-12 >= next_remodel_[t]) remodel(t);
  if (!bleeding_tissues_.empty()) bleed(dt);
}

void Simulation::open_wound(std::size_t t, const Vec3& rest) {
  if (t >= bleeding_index_.size() || bleeding_index_[t] < 0) return;
  const auto b = static_cast<std::size_t>(bleeding_index_[t]);
  const TissueBody& tissue = *world_.tissues[t];
  if (tissue.settings.vertex_count() == 0) return;
  // One wound per bleeding point: a cut that goes on, a tear that pulls on, widen the one there.
  constexpr Real kSamePoint = 0.003;
  for (const Bleeding::Wound& w : bleeding_.wounds())
    if (w.tissue == b && (w.state == WoundState::kBleeding || w.state == WoundState::kNeedsClip) &&
        w.vertex < tissue.settings.vertex_count() &&
        (tissue.settings.rest_positions[w.vertex] - rest).norm() < kSamePoint)
      return;
  bleeding_.open_wound(b, nearest_vertex(tissue.settings.rest_positions, rest), *tissue.bleeds, bleeding_.time());
}

std::int64_t Simulation::clip_at(std::size_t i, Real reach) {
  if (i >= world_.instruments.size() || phase_[i] != PortPhase::kInside) return -1;
  const Vec3& tip = world_.instruments[i].instrument.pose().translation;
  std::int64_t nearest = -1;
  Real best = reach;
  for (std::size_t w = 0; w < bleeding_.wounds().size(); ++w) {
    const Bleeding::Wound& wound = bleeding_.wounds()[w];
    if (wound.state != WoundState::kBleeding && wound.state != WoundState::kNeedsClip) continue;
    const TissueBody& tissue = *world_.tissues[bleeding_tissues_[wound.tissue]];
    if (wound.vertex >= tissue.state.positions.size()) continue;
    const Real d = (tissue.state.positions[wound.vertex] - tip).norm();
    if (d <= best) best = d, nearest = static_cast<std::int64_t>(w);
  }
  if (nearest >= 0) bleeding_.clip(static_cast<std::size_t>(nearest));
  return nearest;
}

void Simulation::bleed(Real dt) {
  // Heat at an open wound coagulates it: the largest Ω of the triangles around its vertex, applied
  // while it rises (the electrode there now).
  for (std::size_t w = 0; w < bleeding_.wounds().size(); ++w) {
    const Bleeding::Wound& wound = bleeding_.wounds()[w];
    if (wound.state != WoundState::kBleeding && wound.state != WoundState::kNeedsClip) continue;
    const std::size_t t = bleeding_tissues_[wound.tissue];
    if (!thermal_[t].hot()) continue;
    const MassSpringSettings& s = world_.tissues[t]->settings;
    Real damage = 0;
    for (std::size_t k = 0; k < s.triangles.size(); ++k)
      if (s.triangles[k][0] == wound.vertex || s.triangles[k][1] == wound.vertex || s.triangles[k][2] == wound.vertex)
        damage = std::max(damage, thermal_[t].damage()[k]);
    if (damage > wound.damage) bleeding_.coagulate(w, damage, dt);
  }
  // A grasper pulling a vessel harder than it bears tears it where it holds it.
  for (const std::size_t t : bleeding_tissues_) {
    const TissueBody& tissue = *world_.tissues[t];
    if (!(tissue.tear_force > 0)) continue;
    for (std::size_t i = 0; i < loads_.size(); ++i) {
      if (responses_[t]->held_vertices(i) == 0 || tissue_force(t, i).norm() <= tissue.tear_force) continue;
      const Vec3& at = world_.instruments[i].instrument.pose().translation;
      open_wound(t, tissue.settings.rest_positions[nearest_vertex(tissue.state.positions, at)]);
    }
  }
  bleeding_.step({}, Vec3::Zero(), dt);
}

}  // namespace trocar

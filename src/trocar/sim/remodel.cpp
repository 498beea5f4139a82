// A tissue remodelled by electrosurgery (docs/electrosurgery.md, "Remodelling"): newly coagulated
// triangles stiffen their edge springs at their present length, cut triangles are removed, and
// everything that keeps something per vertex or triangle of the tissue is rebuilt or remapped.
#include <cmath>
#include <unordered_map>

#include "trocar/tissue/cut.h"
#include "trocar/sim/simulation.h"

namespace trocar {
namespace {

/// At most one remodel of a tissue per this much simulated time (s): a burn coagulates a
/// triangle every few steps, and each remodel rebuilds the tissue's solver.
constexpr Real kRemodelPeriod = 0.01;

std::uint64_t pair_key(std::uint32_t a, std::uint32_t b, bool bending) {
  const std::uint64_t lo = std::min(a, b), hi = std::max(a, b);
  return (lo << 33) | (hi << 1) | (bending ? 1u : 0u);
}

}  // namespace

void Simulation::remodel(std::size_t t) {
  TissueBody& old = *world_.tissues[t];
  const ThermalField& field = thermal_[t];
  const std::size_t old_triangles = old.settings.triangles.size();
  std::vector<std::uint32_t>& cut = remodel_cut_;
  std::vector<std::uint32_t>& coagulating = remodel_coagulating_;
  cut.clear();
  coagulating.clear();
  for (std::uint32_t k = 0; k < old_triangles; ++k) {
    if (field.cut(k)) cut.push_back(k);
    if (field.coagulated(k) && !coagulated_[t][k]) coagulating.push_back(k);
  }
  if (cut.empty() && (coagulating.empty() || !(old.coagulation_stiffening != 1))) {
    for (const std::uint32_t k : coagulating) coagulated_[t][k] = 1;
    return;
  }
  next_remodel_[t] = time_ + kRemodelPeriod;
  ++metrics_.remodelled;

  // Coagulation: the triangle's edge springs, once each, stiffer and at rest at their length now.
  MassSpringSettings& current = old.settings;  // springs changed in place when nothing is cut
  std::vector<std::uint32_t>& changed = remodel_changed_;
  std::vector<Spring>& springs_before = remodel_before_;
  changed.clear();
  springs_before.clear();
  if (!coagulating.empty()) {
    std::unordered_map<std::uint64_t, std::uint32_t>& spring_of = spring_of_[t];
    if (spring_of.empty()) {
      spring_of.reserve(current.structural_count);
      for (std::uint32_t s = 0; s < current.structural_count; ++s)
        spring_of.emplace(pair_key(current.springs[s].i, current.springs[s].j, false), s);
    }
    for (const std::uint32_t k : coagulating) {
      coagulated_[t][k] = 1;
      const Triangle& tri = current.triangles[k];
      for (int e = 0; e < 3; ++e) {
        const auto it = spring_of.find(pair_key(tri[e], tri[(e + 1) % 3], false));
        if (it == spring_of.end() || stiffened_[t][it->second]) continue;
        stiffened_[t][it->second] = 1;
        Spring& sp = current.springs[it->second];
        springs_before.push_back(sp);
        changed.push_back(it->second);
        sp.stiffness *= old.coagulation_stiffening;
        const Real length = (old.state.positions[sp.i] - old.state.positions[sp.j]).norm();
        if (std::isfinite(length) && length > 0) sp.rest_length = length;
      }
    }
  }
  // Nothing cut and an integrator that takes new spring constants in place: no rebuild.
  if (cut.empty()) {
    if (old.integrator.springs_changed(changed)) {
      old.energy.springs_changed(changed);
      ++old.model_version;
      return;
    }
  }
  MassSpringSettings model = current;
  // The retired body keeps the settings it was built with (its integrator still refers to them).
  for (std::size_t c = 0; c < changed.size(); ++c) current.springs[changed[c]] = springs_before[c];

  // The cut, and the maps from the new model's vertices and triangles to the old ones.
  std::vector<std::uint32_t> vertex_origin, triangle_origin;
  std::vector<std::uint8_t> stiffened;
  Real cut_damage = 0, cut_area = 0;
  Vec3 cut_centre = Vec3::Zero();
  if (!cut.empty()) {
    CutTopology result = remove_triangles(model, cut);
    model = std::move(result.settings);
    vertex_origin = std::move(result.vertex_origin);
    triangle_origin = std::move(result.triangle_origin);
    stiffened.assign(model.springs.size(), 0);
    for (std::size_t s = 0; s < model.springs.size(); ++s) stiffened[s] = stiffened_[t][result.spring_origin[s]];
    for (const std::uint32_t k : cut) {
      cut_damage = std::max(cut_damage, field.damage()[k]);
      cut_centre += old.settings.rest_areas[k] * (old.settings.rest_positions[old.settings.triangles[k][0]] +
                                                 old.settings.rest_positions[old.settings.triangles[k][1]] +
                                                 old.settings.rest_positions[old.settings.triangles[k][2]]) / 3;
      cut_area += old.settings.rest_areas[k];
      burns_[t].cut_area += old.settings.rest_areas[k];
      ++burns_[t].cut_triangles;
      if (field.coagulated(k)) burns_[t].coagulated_area += old.settings.rest_areas[k];
    }
    metrics_.triangles_cut += static_cast<std::uint32_t>(cut.size());
  } else {
    vertex_origin.resize(model.vertex_count());
    for (std::uint32_t v = 0; v < vertex_origin.size(); ++v) vertex_origin[v] = v;
    triangle_origin.resize(old_triangles);
    for (std::uint32_t k = 0; k < triangle_origin.size(); ++k) triangle_origin[k] = k;
    stiffened = stiffened_[t];
  }

  // The new body: the old one's state through the maps, its integrator's options and settings.
  const MassSpringIntegrator& integrator = old.integrator;
  const XpbdOptions xpbd = integrator.kind() == IntegratorKind::kXpbd
                               ? integrator.xpbd()->options()
                               : XpbdOptions{};
  auto body = std::make_unique<TissueBody>(old.name, std::move(model), integrator.kind(), integrator.implicit_options(),
                                           xpbd);
  body->integrator.terms() = integrator.terms();
  if (!integrator.simd()) body->integrator.set_simd(false);
  for (std::size_t v = 0; v < vertex_origin.size(); ++v) {
    body->state.positions[v] = old.state.positions[vertex_origin[v]];
    body->state.velocities[v] = old.state.velocities[vertex_origin[v]];
  }
  if (old.texcoords.size() == 3 * old_triangles) {
    body->texcoords.resize(3 * triangle_origin.size());
    for (std::size_t k = 0; k < triangle_origin.size(); ++k)
      for (int c = 0; c < 3; ++c) body->texcoords[3 * k + c] = old.texcoords[3 * triangle_origin[k] + c];
  }
  body->graspable = old.graspable;
  body->enters_at = old.enters_at;
  body->thermal = old.thermal;
  body->coagulation_stiffening = old.coagulation_stiffening;
  body->bleeds = old.bleeds;
  body->tear_force = old.tear_force;
  body->model_version = old.model_version + 1;

  // Everything that keeps something of this tissue. The step's contacts name the old triangles;
  // they are used up (the next step detects again).
  contacts_.clear();
  std::vector<std::uint8_t> coagulated(triangle_origin.size());
  for (std::size_t k = 0; k < triangle_origin.size(); ++k) coagulated[k] = coagulated_[t][triangle_origin[k]];
  thermal_[t].remap(triangle_origin, body->settings.triangles, body->settings.rest_positions, body->settings.rest_areas);
  std::unique_ptr<TissueBody> retired = std::move(world_.tissues[t]);
  world_.tissues[t] = std::move(body);
  TissueBody& now = *world_.tissues[t];
  const std::size_t ni = world_.instruments.size();
  objects_[ni + t] = {ObjectRole::kTissue, now.state.positions, now.settings.triangles};
  detector_.broad_phase().remap_object(ni + t, triangle_origin);  // its clusters keep their order
  responses_[t]->remodel({&now.settings, &now.state, &now.loads, &now.integrator, static_cast<std::uint32_t>(ni + t)},
                         vertex_origin);
  tissue_contact_->remodel(t, {&now.settings, &now.state}, triangle_origin, old_triangles, time_);
  meter_->remodel(t);
  tissue_masses_[t] = now.settings.total_mass();
  coagulated_[t] = std::move(coagulated);
  stiffened_[t] = std::move(stiffened);
  size_burn(t);
  // A cut vessel bleeds unless what was cut had coagulated enough to seal it (a vessel the hook can
  // seal: cutting through coagulated tissue is how surgeons keep small vessels from bleeding).
  if (bleeding_index_[t] >= 0) {
    const auto b = static_cast<std::size_t>(bleeding_index_[t]);
    bleeding_.remap_tissue(b, vertex_origin, now.settings.triangles, now.settings.rest_positions);
    if (!cut.empty() && cut_area > 0) {
      const BleedingProperties& p = bleeding_.properties();
      const bool sealed = now.bleeds->diameter <= seal_limit(p, EnergyModality::kMonopolar) &&
                          cut_damage >= seal_threshold(p, *now.bleeds);
      if (!sealed) open_wound(t, cut_centre / cut_area);
    }
  }
}

}  // namespace trocar

#include "trocar/tissue/state.h"

#include <cassert>

#include "trocar/tissue/settings.h"

namespace trocar {

MassSpringState MassSpringState::at_rest(const MassSpringSettings& settings) {
  return {settings.rest_positions, std::vector<Vec3>(settings.rest_positions.size(), Vec3::Zero())};
}

void TissueLoads::reset(std::size_t vertex_count, std::size_t max_contacts) {
  forces_.assign(vertex_count, Vec3::Zero());
  is_loaded_.assign(vertex_count, 0);
  loaded_.clear();
  loaded_.reserve(vertex_count);
  contacts.clear();
  contacts.reserve(max_contacts);
}

void TissueLoads::clear() {
  for (const std::uint32_t v : loaded_) {
    forces_[v] = Vec3::Zero();
    is_loaded_[v] = 0;
  }
  loaded_.clear();
  contacts.clear();
}

void TissueLoads::add_force(std::uint32_t vertex, const Vec3& f) {
  assert(vertex < forces_.size());
  if (is_loaded_[vertex] == 0) {
    is_loaded_[vertex] = 1;
    loaded_.push_back(vertex);
  }
  forces_[vertex] += f;
}

bool yield_home(MassSpringSettings& settings, const MassSpringState& state) {
  const Real yield = settings.home_yield;
  if (!(yield > 0) || settings.k_home == 0) return false;
  bool moved = false;
  for (std::size_t i = 0; i < settings.vertex_count(); ++i) {
    if (settings.fixed[i]) continue;
    const Vec3 stretch = state.positions[i] - settings.home_positions[i];
    const Real length = stretch.norm();
    if (!(length > yield)) continue;  // within the yield (or not finite: left to the stability check)
    settings.home_positions[i] += (1 - yield / length) * stretch;
    moved = true;
  }
  return moved;
}

}  // namespace trocar

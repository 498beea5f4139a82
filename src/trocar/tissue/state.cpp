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

}  // namespace trocar

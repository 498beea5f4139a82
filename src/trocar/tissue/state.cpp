#include "trocar/tissue/state.h"

#include "trocar/tissue/settings.h"

namespace trocar {

MassSpringState MassSpringState::at_rest(const MassSpringSettings& settings) {
  return {settings.rest_positions, std::vector<Vec3>(settings.rest_positions.size(), Vec3::Zero())};
}

void TissueLoads::reset(std::size_t vertex_count, std::size_t max_contacts) {
  forces.assign(vertex_count, Vec3::Zero());
  contacts.clear();
  contacts.reserve(max_contacts);
}

void TissueLoads::clear() {
  std::fill(forces.begin(), forces.end(), Vec3::Zero());
  contacts.clear();
}

}  // namespace trocar

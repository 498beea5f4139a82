#include "trocar/tissue/energy.h"

#include <cassert>

#include "trocar/tissue/forces.h"
#include "trocar/tissue/internal.h"

namespace trocar {

ElasticEnergyMeter::ElasticEnergyMeter(const MassSpringSettings& settings) : settings_(settings) {
  springs_ = tissue_detail::make_spring_layout(settings.springs, settings.vertex_count());
  arrays_.allocate(settings.vertex_count(), 1);
  x_ = arrays_[0];
  use_avx2_ = cpu_has_avx2_fma();
}

void ElasticEnergyMeter::springs_changed(std::span<const std::uint32_t> springs) {
  for (const std::uint32_t s : springs) tissue_detail::set_spring_constants(springs_, s, settings_.springs[s]);
}

Real ElasticEnergyMeter::elastic(std::span<const Vec3> x) {
  const MassSpringSettings& s = settings_;
  assert(x.size() == s.vertex_count());
  tissue_detail::copy_padded(x.data(), x.size(), x_.data());
  Real e = tissue_detail::spring_energy_padded(springs_, x_.data(), use_avx2_);
  ForceTerms others;  // area (rarely on) and home springs (one cheap vertex pass): the reference code
  others.springs = false;
  others.volume = false;
  others.gravity = false;
  others.global_damping = false;
  e += potential_energy(s, x, others);
  if (tissue_detail::volume_term_on(s, ForceTerms{}))
    e += tissue_detail::volume_energy(s, tissue_detail::six_volume_padded(s, x_.data(), use_avx2_) / 6.0);
  return e;
}

}  // namespace trocar

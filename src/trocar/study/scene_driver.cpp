#include "trocar/study/scene_driver.h"

#include <cmath>

#include "trocar/core/stability.h"

namespace trocar {

std::size_t step_count(Real duration, Real dt) {
  return static_cast<std::size_t>(std::ceil(duration / dt - 1e-9));
}

Real tissue_mass(const World& world) {
  Real mass = 0;
  for (const auto& tissue : world.tissues) mass += tissue->settings.total_mass();
  return mass;
}

Simulation make_simulation(Scene& scene) { return Simulation(std::move(scene.world), scene.settings); }

bool step_is_stable(const StepMetrics& metrics, Real tissue_mass) {
  return is_stable(metrics.finite, metrics.kinetic_energy, tissue_mass, metrics.tissue_rms_speed);
}

DriveResult drive(Simulation& sim, Real dt, std::size_t steps) {
  return drive(sim, dt, steps, [](const StepMetrics&) {});
}

}  // namespace trocar

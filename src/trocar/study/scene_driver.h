#pragma once
/// The one stepping loop of a Simulation at a fixed time step, shared by `trocar run`, the studies
/// (penetration, robustness) and the benchmarks' warm-ups: step, hand the step's metrics to the
/// caller, stop at the first state that is not stable (core/stability.h, docs/stability.md).
#include <cstddef>

#include "trocar/core/types.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"

namespace trocar {

/// The steps that cover `duration` seconds at `dt`: ⌈duration / dt⌉, where a duration within
/// 10⁻⁹ of a step of a whole count (a rounding error of the sum) does not add a step.
std::size_t step_count(Real duration, Real dt);

/// Σ of the tissues' vertex masses (kg): what the stability bound scales with.
Real tissue_mass(const World& world);

/// The scene's world and settings as a Simulation (the scene's world is moved out).
Simulation make_simulation(Scene& scene);

/// is_stable() (core/stability.h) of a step's state in a world of `tissue_mass` kg.
bool step_is_stable(const StepMetrics& metrics, Real tissue_mass);

/// What drive() did.
struct DriveResult {
  std::size_t steps = 0;  ///< steps taken, the first unstable one included
  bool stable = true;     ///< every step's state stable
};

/// Steps `sim` up to `steps` times at `dt`. After each step, `on_step(metrics)` sees the step's
/// metrics (the simulation's state is that step's); the loop then stops if the state is not
/// stable (is_stable() with the world's tissue mass).
template <typename OnStep>
DriveResult drive(Simulation& sim, Real dt, std::size_t steps, OnStep&& on_step) {
  const Real mass = tissue_mass(sim.world());
  DriveResult result;
  while (result.steps < steps) {
    const StepMetrics& m = sim.step(dt);
    ++result.steps;
    on_step(m);
    if (!step_is_stable(m, mass)) {
      result.stable = false;
      break;
    }
  }
  return result;
}

/// drive() with nothing to collect (warm-ups).
DriveResult drive(Simulation& sim, Real dt, std::size_t steps);

}  // namespace trocar

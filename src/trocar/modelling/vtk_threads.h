#pragma once
/// VTK's threading, fixed for determinism.

namespace trocar {

/// Makes VTK run its filters on one thread (the Sequential SMP backend), so that builds are
/// deterministic and timed on one core. Idempotent.
void use_one_vtk_thread();

}  // namespace trocar

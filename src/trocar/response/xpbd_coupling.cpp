#include "trocar/response/xpbd_coupling.h"

namespace trocar {

void step_coupled(std::span<const CoupledTissue> tissues, TissueContactSolver& contact, Real dt, int substeps,
                  Real time, std::span<XpbdStats> stats) {
  for (const CoupledTissue& c : tissues)
    if (c.solver != nullptr) c.solver->begin(*c.state, *c.loads, dt, c.contacts, substeps);
  contact.begin_coupled(tissues, dt, substeps);
  const Real h = dt / substeps;
  for (int s = 0; s < substeps; ++s) {
    for (const CoupledTissue& c : tissues)
      if (c.solver != nullptr) c.solver->substep_constraints(s);
    for (const CoupledTissue& c : tissues)
      if (c.solver != nullptr) c.solver->substep_contacts(s);
    contact.solve_coupled_positions(h);
    for (const CoupledTissue& c : tissues)
      if (c.solver != nullptr) c.solver->substep_velocities();
    contact.solve_coupled_velocities(h);
  }
  for (std::size_t t = 0; t < tissues.size(); ++t)
    if (tissues[t].solver != nullptr) stats[t] = tissues[t].solver->finish(*tissues[t].state);
  contact.end_coupled(time);
}

}  // namespace trocar

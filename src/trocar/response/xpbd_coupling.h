#pragma once
/// Tissues stepped by XPBD in lock-step, with the contacts and tacks between them solved inside
/// their substeps (TissueContactSolver, coupled; docs/response.md, "Tissue against tissue").
#include <span>

#include "trocar/core/types.h"
#include "trocar/response/tissue_contact.h"
#include "trocar/tissue/state.h"
#include "trocar/tissue/xpbd.h"

namespace trocar {

/// Steps every tissue with a solver by dt in `substeps` substeps: per substep, each tissue's own
/// constraints and its instrument contacts, then one pass over the contacts and tacks between the
/// tissues (moving both sides), then the velocities Δx/h and the velocity passes (tissue_contact.h
/// says why the tissue pass comes last). `contact.begin_step()` must have been
/// called with the states at the step's start, and `contact.can_couple` must hold for these
/// solvers. Writes each stepped tissue's statistics into stats[t]. No allocation after warm-up.
void step_coupled(std::span<const CoupledTissue> tissues, TissueContactSolver& contact, Real dt, int substeps,
                  Real time, std::span<XpbdStats> stats);

}  // namespace trocar

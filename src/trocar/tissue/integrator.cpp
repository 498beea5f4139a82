// Placeholder: the integrators land here. Replace this whole file.
#include "trocar/tissue/integrator.h"

#include "trocar/core/error.h"

namespace trocar {

const char* integrator_name(IntegratorKind) { return "none"; }
IntegratorKind integrator_from_name(std::string_view) { throw Error("not implemented"); }
MassSpringIntegrator::MassSpringIntegrator(const MassSpringSettings& settings, IntegratorKind kind,
                                           ImplicitOptions options)
    : settings_(settings), kind_(kind), options_(options) {}
StepStats MassSpringIntegrator::step(MassSpringState&, const TissueLoads&, Real) { return {}; }

}  // namespace trocar

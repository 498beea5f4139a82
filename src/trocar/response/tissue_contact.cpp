#include "trocar/response/tissue_contact.h"

#include <limits>

namespace trocar {

// STUB (contract only): the contact and attachment solve are being written.

TissueContactSolver::TissueContactSolver(std::vector<ContactTissue> tissues, std::vector<TissueContactPair> pairs,
                                         std::size_t attachment_capacity)
    : tissues_(std::move(tissues)), pairs_(std::move(pairs)), capacity_(attachment_capacity) {
  attachments_.reserve(capacity_);
}

TissueContactSolver::~TissueContactSolver() = default;

void TissueContactSolver::begin_step() {}

void TissueContactSolver::solve(Real /*dt*/, Real /*time*/) {}

std::size_t TissueContactSolver::attach(const AttachmentSpec& spec) {
  if (attachments_.size() >= capacity_) return std::numeric_limits<std::size_t>::max();
  for (const SurfacePoint* p : {&spec.a, &spec.b})
    if (p->tissue >= tissues_.size() || p->triangle >= tissues_[p->tissue].settings->triangles.size())
      return std::numeric_limits<std::size_t>::max();
  attachments_.push_back({spec, true, 0, -1});
  return attachments_.size() - 1;
}

Vec3 surface_position(const MassSpringSettings& settings, const MassSpringState& state, const SurfacePoint& p) {
  const Triangle& t = settings.triangles[p.triangle];
  return p.bary[0] * state.positions[t[0]] + p.bary[1] * state.positions[t[1]] + p.bary[2] * state.positions[t[2]];
}

}  // namespace trocar

#include "trocar/response/tissue_response.h"

#include "trocar/core/timer.h"
#include "trocar/response/contact_projection.h"

namespace trocar {
namespace {

/// A penalty force per detected contact (obb, primitive, normal, project): one ResponseSolver per
/// instrument holds that pair's grasp and position corrections.
class PenaltyResponse : public TissueResponse {
 public:
  PenaltyResponse(const ResponseTissue& tissue, std::span<const ResponseInstrument> instruments,
                  const ResponseSettings& settings)
      : tissue_(tissue), instruments_(instruments.begin(), instruments.end()) {
    solvers_.reserve(instruments.size());
    for (std::size_t i = 0; i < instruments.size(); ++i) {
      solvers_.emplace_back(settings);
      solvers_.back().reset(tissue.settings->vertex_count());
    }
  }

  void before_integration(std::span<const Contact> contacts, std::span<InstrumentLoad> loads,
                          ResponseTally& tally) override {
    const TissueView view{tissue_.state->positions, tissue_.state->velocities, tissue_.settings->triangles};
    for (std::size_t i = 0; i < solvers_.size(); ++i) {
      InstrumentLoad pair;
      const ResponseStats stats = solvers_[i].apply(contacts, static_cast<std::uint32_t>(i), tissue_.object,
                                                    *instruments_[i].instrument, view, *tissue_.loads, pair);
      tally.contacts += stats.considered;
      tally.applied += stats.count(ContactStatus::kApplied);
      loads[i].raw_force += pair.raw_force;
      loads[i].raw_torque += pair.raw_torque;
    }
  }

  void after_integration(std::span<const Contact> /*contacts*/, Real /*dt*/, std::span<InstrumentLoad> /*loads*/,
                         ResponseTally& /*tally*/) override {
    for (std::size_t i = 0; i < solvers_.size(); ++i) {
      solvers_[i].apply_corrections(tissue_.state->positions);
      solvers_[i].apply_grasp(*instruments_[i].instrument, tissue_.state->positions, tissue_.state->velocities);
    }
  }

  std::size_t held_vertices(std::size_t i) const override { return solvers_[i].grasp().held().size(); }

  void remodel(const ResponseTissue& tissue, std::span<const std::uint32_t> vertex_origin) override {
    tissue_ = tissue;
    for (ResponseSolver& solver : solvers_) solver.remodel(vertex_origin);
  }

 protected:
  ResponseTissue tissue_;
  std::vector<ResponseInstrument> instruments_;
  std::vector<ResponseSolver> solvers_;  ///< per instrument
};

/// sdf: the penalty pass (grasps, counts), then after the integrator the tissue is projected out
/// of every instrument's signed distance (response/contact_projection.h).
class ProjectionResponse final : public PenaltyResponse {
 public:
  ProjectionResponse(const ResponseTissue& tissue, std::span<const ResponseInstrument> instruments,
                     const ResponseSettings& settings)
      : PenaltyResponse(tissue, instruments, settings), projectors_(instruments.size()) {
    for (std::size_t i = 0; i < instruments.size(); ++i) {
      projectors_[i].reset(tissue.settings->vertex_count(), tissue.settings->triangles,
                           instruments[i].instrument->world_positions().size());
      projectors_[i].size_for(*instruments[i].field);
    }
  }

  void after_integration(std::span<const Contact> contacts, Real dt, std::span<InstrumentLoad> loads,
                         ResponseTally& tally) override {
    PenaltyResponse::after_integration(contacts, dt, loads, tally);
    const Timer timer;
    const MassSpringSettings& s = *tissue_.settings;
    const ProjectedTissue view{tissue_.state->positions, tissue_.state->velocities, s.masses, s.fixed, s.triangles};
    for (std::size_t i = 0; i < projectors_.size(); ++i) {
      const ResponseInstrument& in = instruments_[i];
      const ProjectionStats stats =
          projectors_[i].project(*in.instrument, *in.field, contacts, static_cast<std::uint32_t>(i), tissue_.object,
                                 solvers_[i].grasp(), view, in.thickness, dt, solvers_[i].settings());
      loads[i].raw_force += stats.force;
      loads[i].raw_torque += stats.torque;
    }
    tally.after_us += timer.microseconds();
  }

  std::span<const std::uint8_t> instrument_hits(std::size_t i) const override {
    return projectors_[i].instrument_hits();
  }

  void remodel(const ResponseTissue& tissue, std::span<const std::uint32_t> vertex_origin) override {
    PenaltyResponse::remodel(tissue, vertex_origin);
    for (std::size_t i = 0; i < projectors_.size(); ++i) {
      projectors_[i].reset(tissue.settings->vertex_count(), tissue.settings->triangles,
                           instruments_[i].instrument->world_positions().size());
      projectors_[i].size_for(*instruments_[i].field);
    }
  }

 private:
  std::vector<ContactProjector> projectors_;  ///< per instrument
};

/// xpbd: contact is a constraint inside every substep of the tissue's solver
/// (response/solver_contact.h); the detected pairs are not used. After the integrator it reports
/// the mean constraint force.
class SolverContactResponse final : public TissueResponse {
 public:
  SolverContactResponse(const ResponseTissue& tissue, std::span<const ResponseInstrument> instruments,
                        const ResponseSettings& settings) {
    std::vector<SolverInstrument> inputs;
    for (const ResponseInstrument& in : instruments) inputs.push_back({in.instrument, in.field, in.thickness});
    contacts_.reset(tissue.settings->rest_positions, tissue.settings->triangles, tissue.settings->closed, inputs,
                    settings);
    tissue.integrator->set_contacts(&contacts_);
    instruments_ = instruments.size();
  }

  void before_integration(std::span<const Contact> /*contacts*/, std::span<InstrumentLoad> /*loads*/,
                          ResponseTally& /*tally*/) override {}

  void after_integration(std::span<const Contact> /*contacts*/, Real /*dt*/, std::span<InstrumentLoad> loads,
                         ResponseTally& tally) override {
    tally.contacts += contacts_.contacts();
    tally.applied += contacts_.contacts();
    for (std::size_t i = 0; i < instruments_; ++i) {
      loads[i].raw_force += contacts_.force(i);
      loads[i].raw_torque += contacts_.torque(i);
    }
  }

  std::span<const std::uint8_t> instrument_hits(std::size_t i) const override { return contacts_.hits(i); }
  std::span<const SolverContactPoint> contact_points(std::size_t i) const override { return contacts_.points(i); }
  std::size_t held_vertices(std::size_t i) const override { return contacts_.held(i).size(); }

  void remodel(const ResponseTissue& tissue, std::span<const std::uint32_t> vertex_origin) override {
    contacts_.remodel(tissue.settings->rest_positions, tissue.settings->triangles, tissue.settings->closed,
                      vertex_origin);
    tissue.integrator->set_contacts(&contacts_);
  }

 private:
  InstrumentContacts contacts_;
  std::size_t instruments_ = 0;
};

}  // namespace

bool needs_instrument_field(IntegratorKind integrator, const ResponseSettings& settings) {
  return integrator == IntegratorKind::kXpbd || settings.method == ResponseMethod::kSdf;
}

std::unique_ptr<TissueResponse> make_tissue_response(const ResponseTissue& tissue,
                                                     std::span<const ResponseInstrument> instruments,
                                                     const ResponseSettings& settings) {
  if (tissue.integrator->kind() == IntegratorKind::kXpbd)
    return std::make_unique<SolverContactResponse>(tissue, instruments, settings);
  if (settings.method == ResponseMethod::kSdf)
    return std::make_unique<ProjectionResponse>(tissue, instruments, settings);
  return std::make_unique<PenaltyResponse>(tissue, instruments, settings);
}

}  // namespace trocar

#include "trocar/sim/view_snapshot.h"

#include <algorithm>
#include <cmath>

namespace trocar {
namespace {

/// Tissue t's burn per vertex (ViewSnapshot::tissue_effects); empty while nothing heated it.
void capture_effects(const Simulation& sim, std::size_t t, std::vector<float>& out) {
  const ThermalField& field = sim.thermal(t);
  if (!(field.delivered() > 0)) {
    out.clear();
    return;
  }
  const MassSpringSettings& s = sim.world().tissues[t]->settings;
  out.assign(4 * s.vertex_count(), 0.0f);
  for (std::size_t k = 0; k < s.triangles.size() && k < field.size(); ++k) {
    const float coagulation = static_cast<float>(1 - std::exp(-field.damage()[k]));
    const float charring = static_cast<float>(std::min<Real>(1, field.vaporised()[k]));
    for (const std::uint32_t v : s.triangles[k]) {
      out[4 * v] = std::max(out[4 * v], coagulation);
      out[4 * v + 1] = std::max(out[4 * v + 1], charring);
    }
  }
}

}  // namespace

void capture_view(const Simulation& sim, ViewSnapshot& out) {
  const World& world = sim.world();
  out.time = sim.time();
  out.step = sim.metrics().step_index;
  out.timings = sim.metrics().timings;
  const OhcStats* ohc = sim.detector().ohc_stats();
  out.cell_size = ohc ? ohc->cell_size : 0;
  out.tissues.resize(world.tissues.size());
  out.tissue_versions.resize(world.tissues.size(), ~0u);
  out.tissue_triangles.resize(world.tissues.size());
  out.tissue_rest.resize(world.tissues.size());
  out.tissue_bleeds.resize(world.tissues.size());
  out.tissue_effects.resize(world.tissues.size());
  for (std::size_t t = 0; t < world.tissues.size(); ++t) {
    const TissueBody& tissue = *world.tissues[t];
    const auto& x = tissue.state.positions;
    out.tissues[t].assign(x.begin(), x.end());
    if (out.tissue_versions[t] != tissue.model_version) {
      out.tissue_versions[t] = tissue.model_version;
      out.tissue_triangles[t] = tissue.settings.triangles;
      out.tissue_rest[t] = tissue.settings.rest_positions;
    }
    out.tissue_bleeds[t] = tissue.bleeds ? 1 : 0;
    capture_effects(sim, t, out.tissue_effects[t]);
  }
  out.vapour.assign(sim.vapour().begin(), sim.vapour().end());
  out.wounds.clear();
  for (const Bleeding::Wound& w : sim.bleeding().wounds())
    out.wounds.push_back({static_cast<std::uint32_t>(sim.bleeding_tissue(w.tissue)), w.vertex, w.emitted,
                          w.state == WoundState::kBleeding || w.state == WoundState::kNeedsClip});
  const std::size_t ni = world.instruments.size();
  out.instruments.resize(ni);
  const auto metrics = sim.instrument_metrics();
  for (std::size_t i = 0; i < ni; ++i) {
    const Instrument& inst = world.instruments[i].instrument;
    InstrumentView& v = out.instruments[i];
    v.pose = inst.pose();
    v.jaw = inst.jaw();
    v.obb = inst.world_obb();
    v.force = i < metrics.size() ? metrics[i].force : Vec3::Zero();
    v.contact_centre = Vec3::Zero();
    v.contacts = 0;
    v.tip = inst.pose().translation;
    const Vec3 back = inst.top_world() - v.tip;
    v.forward = back.norm() > 0 ? Vec3(-back.normalized()) : Vec3::UnitZ();
    v.suction_spec = world.instruments[i].suction;
    v.suction = sim.suction_on(i) && !sim.parked(i);
    v.irrigation = sim.irrigation_on(i) && !sim.parked(i);
    v.energy = sim.energy_on(i) && !sim.parked(i);
  }
  // Object order in contacts: instruments, then tissues, then rigids (Simulation's objects_).
  const std::size_t nt = world.tissues.size();
  out.contacts.clear();
  for (const Contact& c : sim.contacts()) {
    if (c.kind != ContactKind::kInstrumentTissue) continue;
    const std::uint32_t inst = c.object_a < ni ? c.object_a : c.object_b;
    const std::uint32_t tissue_object = c.object_a < ni ? c.object_b : c.object_a;
    const std::uint32_t tri = c.object_a < ni ? c.triangle_b : c.triangle_a;
    if (inst >= ni || tissue_object < ni || tissue_object >= ni + nt) continue;
    const TissueBody& tissue = *world.tissues[tissue_object - ni];
    if (tri >= tissue.settings.triangles.size()) continue;
    const Triangle& f = tissue.settings.triangles[tri];
    const auto& x = tissue.state.positions;
    Vec3 n = (x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]);
    const Real len = n.norm();
    ContactView cv;
    cv.point = 0.5 * (c.segment_p + c.segment_q);
    cv.normal = len > 0 ? Vec3(n / len) : Vec3::Zero();
    cv.instrument = inst;
    out.contacts.push_back(cv);
    out.instruments[inst].contact_centre += cv.point;
    ++out.instruments[inst].contacts;
  }
  // Contacts a tissue's response found itself (xpbd keeps the instrument outside, so no triangle
  // pairs intersect): the ones its solver answered in its last substep.
  for (std::size_t t = 0; t < nt; ++t)
    for (std::size_t i = 0; i < ni; ++i)
      for (const SolverContactPoint& p : sim.response(t).contact_points(i)) {
        out.contacts.push_back({p.point, p.normal, static_cast<std::uint32_t>(i)});
        out.instruments[i].contact_centre += p.point;
        ++out.instruments[i].contacts;
      }
  for (InstrumentView& v : out.instruments)
    v.contact_centre = v.contacts > 0 ? Vec3(v.contact_centre / Real(v.contacts)) : v.pose.translation;
  out.tacks.clear();
  for (const AttachmentState& a : sim.attachments()) {
    if (!a.holding) continue;
    const SurfacePoint& on = a.spec.a;
    const SurfacePoint& into = a.spec.b;
    if (on.tissue >= nt || into.tissue >= nt) continue;
    const TissueBody& first = *world.tissues[on.tissue];
    const TissueBody& second = *world.tissues[into.tissue];
    if (on.triangle >= first.settings.triangles.size() || into.triangle >= second.settings.triangles.size()) continue;
    const Triangle& f = second.settings.triangles[into.triangle];
    const auto& x = second.state.positions;
    const Vec3 n = (x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]);
    const Real len = n.norm();
    out.tacks.push_back({surface_position(first.settings, first.state, on), len > 0 ? Vec3(n / len) : Vec3::UnitZ()});
  }
}

}  // namespace trocar

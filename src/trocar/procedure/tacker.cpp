#include "trocar/procedure/tacker.h"

#include <cmath>
#include <numbers>

#include "trocar/geometry/closest_point.h"

namespace trocar {

const char* to_string(TackOutcome outcome) {
  switch (outcome) {
    case TackOutcome::kFixed: return "fixed";
    case TackOutcome::kTissueOnly: return "tissue only";
    case TackOutcome::kMeshOnly: return "mesh only";
    case TackOutcome::kNothing: return "nothing";
  }
  return "nothing";
}

TackerTip tacker_tip(const Instrument& instrument, const TackerRules& rules) {
  const Obb& box = instrument.local_obb();
  Vec3 tip_local, axis_local;
  if (rules.tip_local && rules.axis_local) {
    tip_local = *rules.tip_local;
    axis_local = *rules.axis_local;
  } else {
    // The top vertex is the handle's end of the shaft (instrument.h); the tip is the other end of
    // the box's long axis.
    const Vec3 a0 = box.axes.col(0);
    const auto& local = instrument.local_mesh().positions;
    const Vec3 top = local.empty() ? box.center : local[instrument.top_vertex()];
    const Real side = a0.dot(top - box.center) > 0 ? -1.0 : 1.0;
    axis_local = side * a0;
    tip_local = box.center + axis_local * box.half_extents.x();
    if (rules.tip_local) tip_local = *rules.tip_local;
    if (rules.axis_local) axis_local = *rules.axis_local;
  }
  const Real len = axis_local.norm();
  const Vec3 axis = len > 0 ? Vec3(axis_local / len) : Vec3(0, 0, -1);
  return {instrument.pose().apply(tip_local), instrument.pose().apply_vector(axis)};
}

SurfaceHit closest_surface_point(const TissueBody& tissue, std::uint32_t t, const Vec3& p) {
  SurfaceHit best;
  const auto& x = tissue.state.positions;
  const auto& tris = tissue.settings.triangles;
  for (std::size_t k = 0; k < tris.size(); ++k) {
    const Triangle& tri = tris[k];
    const TriangleClosestPoint c = closest_point_on_triangle(p, x[tri[0]], x[tri[1]], x[tri[2]]);
    const Real d = (c.point - p).norm();
    if (d < best.distance) {
      best.distance = d;
      best.point = {t, static_cast<std::uint32_t>(k), c.barycentric};
    }
  }
  return best;
}

SurfaceHit closest_surface_point(const TissueBody& tissue, std::uint32_t t, const TackerTip& tip, Real radius) {
  SurfaceHit best = closest_surface_point(tissue, t, tip.point);
  if (!(radius > 0)) return best;
  // Two unit vectors across the axis.
  const Vec3 u = tip.axis.unitOrthogonal(), v = tip.axis.cross(u);
  constexpr int kRim = 12;
  for (int k = 0; k < kRim; ++k) {
    const Real a = 2 * std::numbers::pi_v<Real> * k / kRim;
    const SurfaceHit hit = closest_surface_point(tissue, t, Vec3(tip.point + radius * (std::cos(a) * u + std::sin(a) * v)));
    if (hit.distance < best.distance) best = hit;
  }
  return best;
}

TackRecord fire_tacker(Simulation& sim, std::size_t instrument, const TackerRules& rules,
                       std::span<const NamedZone> zones, std::span<const NamedPoint> landmarks) {
  const World& world = sim.world();
  TackRecord r;
  r.time = sim.time();
  r.instrument = instrument;
  const TackerTip tip = tacker_tip(world.instruments[instrument].instrument, rules);
  r.tip = tip.point;

  bool mesh_hit = false;
  SurfaceHit tissue_hit;
  for (std::size_t t = 0; t < world.tissues.size(); ++t) {
    const SurfaceHit hit = closest_surface_point(*world.tissues[t], static_cast<std::uint32_t>(t), tip, rules.tip_radius);
    if (hit.distance > rules.reach) continue;
    if (t == rules.mesh_tissue) {
      mesh_hit = true;
      r.mesh_point = hit.point;
    } else if (hit.distance < tissue_hit.distance) {
      tissue_hit = hit;
      r.tissue = t;
    }
  }
  if (r.tissue != kNoIndex) r.tissue_point = tissue_hit.point;

  if (mesh_hit && r.tissue != kNoIndex) {
    r.outcome = TackOutcome::kFixed;
    AttachmentSpec spec;
    spec.a = r.mesh_point;
    spec.b = r.tissue_point;
    // Held where it lies: the mesh point where it is now relative to the tissue's (the contact's
    // gap between them, and the sideways step between two points each closest to the tip).
    const TissueBody& mesh = *world.tissues[rules.mesh_tissue];
    const TissueBody& tissue = *world.tissues[r.tissue];
    spec.offset = surface_frame(tissue.settings, tissue.state, spec.b).transpose() *
                  (surface_position(mesh.settings, mesh.state, spec.a) - surface_position(tissue.settings, tissue.state, spec.b));
    spec.pullout_force = rules.pullout_force;
    spec.compliance = rules.compliance;
    r.attachment = sim.attach(spec);
  } else if (r.tissue != kNoIndex) {
    r.outcome = TackOutcome::kTissueOnly;
  } else if (mesh_hit) {
    r.outcome = TackOutcome::kMeshOnly;
  }

  for (const NamedZone& z : zones)
    if (z.contains(r.tip)) {
      r.zone = z.name;
      break;
    }
  for (const NamedPoint& l : landmarks) {
    const Real d = (l.point - r.tip).norm();
    if (r.landmark_distance < 0 || d < r.landmark_distance) {
      r.landmark = l.name;
      r.landmark_distance = d;
    }
  }
  return r;
}

}  // namespace trocar

// The TAPP right groin (inguinal_anatomy.h). Every position below is in the frame of the header;
// docs/anatomy.md gives each size with its source.
#include "trocar/mesh/inguinal_anatomy.h"

#include <algorithm>
#include <cmath>

#include "trocar/core/error.h"
#include "trocar/mesh/inguinal_parts.h"

namespace trocar {
namespace {

// The wall's inner surface is a shallow bowl (radius of curvature 0.35 m, the insufflated wall
// curving toward the camera) round the middle of the groin.
constexpr Real kWallRadius = 0.35;
const Vec2 kBowlCentre(0.05, 0.02);

// Bony landmarks: the pubic tubercle and the anterior superior iliac spine (ASIS); the inguinal
// ligament / iliopubic tract (IPT) runs between them (12 cm, 30° above the x axis).
const Vec2 kPubicTubercle(0.025, 0.0);
const Vec2 kAsis(0.129, 0.060);
// The deep ring at 43 % of the way from the tubercle to the ASIS, 1 cm above the ligament
// (Conaghan et al. 2004: 41 %, CI 26–56 %, along the ligament; 51 % along symphysis–ASIS).
const Vec2 kDeepRing(0.065, 0.035);
// The direct defect in Hesselbach's triangle: medial to the epigastric vessels, above the IPT.
const Vec2 kDirectDefect(0.030, 0.020);
constexpr Real kIncisionY = 0.060;  // the peritoneal incision, well above every defect
constexpr Real kWallX0 = -0.020, kWallX1 = 0.140, kWallY0 = -0.045, kWallY1 = 0.085;
constexpr Real kGap = 0.001;        // clearance kept between structures (m)
constexpr Real kDimpleDepth = 0.003, kDimpleSigma = 0.005;

constexpr Real kDeg = 3.14159265358979323846 / 180;

Vec2 rotate_down(Real degrees_lateral) {  // the unit vector −y turned toward +x
  return Vec2(std::sin(degrees_lateral * kDeg), -std::cos(degrees_lateral * kDeg));
}
// The apex of the triangle of doom: the vas runs 22° medial of straight down, the spermatic
// vessels 18° lateral, 40° apart (O'Malley et al. 1997: 38.6 ± 4.4° on the right).
const Vec2 kVasDir = rotate_down(-22);
const Vec2 kSpermaticDir = rotate_down(18);

struct Look {
  std::array<float, 3> colour;
  float opacity;
};
constexpr Look kMuscle{{0.55f, 0.16f, 0.13f}, 1.0f};
constexpr Look kPeritoneum{{0.95f, 0.66f, 0.66f}, 0.45f};
constexpr Look kFlap{{0.93f, 0.62f, 0.62f}, 0.7f};
constexpr Look kArtery{{0.70f, 0.07f, 0.06f}, 1.0f};
constexpr Look kVein{{0.14f, 0.18f, 0.50f}, 1.0f};
constexpr Look kSpermatic{{0.38f, 0.22f, 0.48f}, 1.0f};
constexpr Look kVas{{0.93f, 0.89f, 0.78f}, 1.0f};
constexpr Look kLigament{{0.95f, 0.95f, 0.90f}, 1.0f};
constexpr Look kBone{{0.89f, 0.84f, 0.70f}, 1.0f};
constexpr Look kFold{{0.90f, 0.76f, 0.70f}, 1.0f};
constexpr Look kSac{{0.93f, 0.60f, 0.58f}, 0.9f};

Real dimple(HerniaKind kind, Real x, Real y) {
  // With a direct hernia the deep ring is closed: a shallow dimple where the cord leaves.
  if (kind != HerniaKind::kDirect) return 0;
  const Real d2 = (Vec2(x, y) - kDeepRing).squaredNorm();
  return kDimpleDepth * std::exp(-d2 / (2 * kDimpleSigma * kDimpleSigma));
}

Vec3 on_wall(const Vec2& p, Real lift = 0) {
  return Vec3(p.x(), p.y(), tapp_wall_height(p.x(), p.y())) + lift * tapp_wall_normal(p.x(), p.y());
}

/// Polygon corners (xy) on the wall's tangent plane at their centroid, lifted along its normal.
NamedZone zone_on_wall(std::string name, const std::vector<Vec2>& corners, Real lift, Real depth) {
  Vec2 c = Vec2::Zero();
  for (const Vec2& p : corners) c += p;
  c /= static_cast<Real>(corners.size());
  const Real z0 = tapp_wall_height(c.x(), c.y());
  const Vec3 n = tapp_wall_normal(c.x(), c.y());
  const Real fx = -n.x() / n.z(), fy = -n.y() / n.z();  // the surface's slopes at c
  NamedZone zone;
  zone.name = std::move(name);
  zone.depth = depth;
  for (const Vec2& p : corners)
    zone.polygon.push_back(Vec3(p.x(), p.y(), z0 + fx * (p.x() - c.x()) + fy * (p.y() - c.y())) + lift * n);
  return zone;
}

/// A strip of half-width w round a polyline (xy), as a polygon, reaching w past either end.
std::vector<Vec2> strip(std::vector<Vec2> line, Real w) {
  line.front() -= w * (line[1] - line[0]).normalized();
  line.back() += w * (line.back() - line[line.size() - 2]).normalized();
  std::vector<Vec2> left, right;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const Vec2 d = (line[std::min(i + 1, line.size() - 1)] - line[i == 0 ? 0 : i - 1]).normalized();
    const Vec2 perp(-d.y(), d.x());
    left.push_back(line[i] + w * perp);
    right.push_back(line[i] - w * perp);
  }
  std::vector<Vec2> out(right.begin(), right.end());
  out.insert(out.end(), left.rbegin(), left.rend());
  return out;
}

/// Builds the tubes one by one: each lies on the wall (its axis a radius and a gap above the
/// surface) and is lifted over the tubes already placed where they cross, with a ramp of slope
/// ≤ 0.7, so no two tubes overlap. A tube `behind` the wall has its axis a radius and a gap below
/// the surface instead (and lifts nothing: its top is under the wall).
class TubeLayer {
 public:
  TubeLayer(HerniaKind kind, const TappOptions& o) : kind_(kind), options_(o) {}

  AnatomyStructure add(std::string name, const std::vector<Vec2>& control, Real radius, const Look& look,
                       StructureRole role, bool behind = false) {
    std::vector<Vec3> flat;
    for (const Vec2& p : control) flat.emplace_back(p.x(), p.y(), 0);
    std::vector<Vec3> dense = smooth_polyline(flat, 0.001);
    std::vector<Real> need(dense.size()), arc(dense.size(), 0);
    for (std::size_t i = 0; i < dense.size(); ++i) {
      Vec3& p = dense[i];
      if (i > 0) arc[i] = arc[i - 1] + (dense[i] - dense[i - 1]).norm();
      const Real wall = tapp_wall_height(p.x(), p.y()) - dimple(kind_, p.x(), p.y());
      need[i] = behind ? wall - radius - kGap : wall + radius + kGap;
      if (behind) continue;
      for (const Placed& other : placed_) {
        const Real reach = radius + other.radius + kGap;
        for (const Vec3& q : other.dense) {
          const Real d = Vec2(p.x() - q.x(), p.y() - q.y()).norm();
          if (d < reach) need[i] = std::max(need[i], q.z() + std::sqrt(reach * reach - d * d));
        }
      }
    }
    constexpr Real kSlope = 0.7;
    for (std::size_t i = 0; i < dense.size(); ++i) {
      Real z = need[i];
      for (std::size_t j = 0; j < dense.size() && !behind; ++j)
        z = std::max(z, need[j] - kSlope * std::abs(arc[i] - arc[j]));
      dense[i].z() = z;
    }
    placed_.push_back({dense, radius});
    AnatomyStructure s;
    s.name = std::move(name);
    s.role = role;
    s.radius = radius;
    s.centreline = smooth_polyline(dense, options_.tube_spacing);
    s.mesh = make_tube(s.centreline, radius, options_.tube_segments);
    s.colour = look.colour;
    s.opacity = look.opacity;
    return s;
  }

 private:
  struct Placed {
    std::vector<Vec3> dense;
    Real radius;
  };
  HerniaKind kind_;
  TappOptions options_;
  std::vector<Placed> placed_;
};

/// A vessel's material: soft, held near its place by strong home springs (it is tethered in the
/// preperitoneal fat), its two end rings fixed where it leaves the field.
void vessel_material(AnatomyStructure& s, std::size_t segments) {
  s.material_preset = "soft";
  s.material = {{"k_structural", 50}, {"k_bending", 5}, {"k_home", 20}};
  const std::size_t rings = (s.mesh.vertex_count() - 2) / segments;
  for (std::size_t j = 0; j < segments; ++j) {
    s.fixed.push_back(static_cast<std::uint32_t>(j));
    s.fixed.push_back(static_cast<std::uint32_t>((rings - 1) * segments + j));
  }
  s.fixed.push_back(static_cast<std::uint32_t>(rings * segments));
  s.fixed.push_back(static_cast<std::uint32_t>(rings * segments + 1));
}

std::size_t grid_count(Real length, Real cell) {
  return static_cast<std::size_t>(std::max<Real>(1, std::round(length / cell)));
}

}  // namespace

const char* hernia_kind_name(HerniaKind kind) { return kind == HerniaKind::kDirect ? "direct" : "indirect"; }

const AnatomyStructure* InguinalAnatomy::find(const std::string& name) const {
  for (const AnatomyStructure& s : structures)
    if (s.name == name) return &s;
  return nullptr;
}

Real tapp_wall_height(Real x, Real y) {
  return (Vec2(x, y) - kBowlCentre).squaredNorm() / (2 * kWallRadius);
}

Vec3 tapp_wall_normal(Real x, Real y) {
  const Vec2 g = (Vec2(x, y) - kBowlCentre) / kWallRadius;  // ∇z
  return Vec3(-g.x(), -g.y(), 1).normalized();
}

InguinalAnatomy make_tapp_anatomy(HerniaKind kind, const TappOptions& o) {
  if (!(o.cell >= 0.002 && o.cell <= 0.01)) throw Error("tapp anatomy: cell must be in [0.002, 0.01] m");
  if (o.tube_segments < 3 || o.tube_segments > 64) throw Error("tapp anatomy: tube_segments must be in [3, 64]");
  if (!(o.tube_spacing >= 0.002 && o.tube_spacing <= 0.02))
    throw Error("tapp anatomy: tube_spacing must be in [0.002, 0.02] m");
  if (o.sac_segments < 8 || o.sac_segments % 4 != 0 || o.sac_segments > 128)
    throw Error("tapp anatomy: sac_segments must be a multiple of 4 in [8, 128]");
  if (o.sac_rings < 2 || o.sac_rings > 64) throw Error("tapp anatomy: sac_rings must be in [2, 64]");
  if (!(o.sac_k_home >= 0)) throw Error("tapp anatomy: sac_k_home must be >= 0");
  if (!(o.sac_home_yield >= 0)) throw Error("tapp anatomy: sac_home_yield must be >= 0");
  const bool direct = kind == HerniaKind::kDirect;
  // EHS 2 defects (1.5–3 cm, Miserez et al. 2007).
  const Real defect_d = o.defect_diameter > 0 ? o.defect_diameter : (direct ? 0.022 : 0.020);
  if (!(defect_d >= 0.01 && defect_d <= 0.024)) throw Error("tapp anatomy: defect_diameter must be in [0.01, 0.024] m");
  const Real sac_length = o.sac_length > 0 ? o.sac_length : (direct ? 0.025 : 0.040);
  if (!(sac_length >= 0.005 && sac_length <= 0.08)) throw Error("tapp anatomy: sac_length must be in [0.005, 0.08] m");

  InguinalAnatomy out;
  out.kind = kind;
  out.defect_radius = defect_d / 2;

  // --- The wall, with the defect as a hole snapped to a grid node.
  const Vec2 wanted = direct ? kDirectDefect : kDeepRing;
  inguinal::SheetSpec wall;
  wall.x0 = kWallX0;
  wall.y0 = kWallY0;
  wall.cell = o.cell;
  wall.nx = grid_count(kWallX1 - kWallX0, o.cell);
  wall.ny = grid_count(kWallY1 - kWallY0, o.cell);
  wall.hole_i = static_cast<std::size_t>(std::lround((wanted.x() - kWallX0) / o.cell));
  wall.hole_j = static_cast<std::size_t>(std::lround((wanted.y() - kWallY0) / o.cell));
  wall.hole_m = static_cast<std::size_t>(std::ceil(0.015 / o.cell - 1e-9));
  wall.hole_r = out.defect_radius;
  wall.hole_rings = 2;
  const Vec2 defect(kWallX0 + o.cell * static_cast<Real>(wall.hole_i), kWallY0 + o.cell * static_cast<Real>(wall.hole_j));
  {
    std::vector<std::uint32_t> border[4];
    AnatomyStructure s;
    s.name = "abdominal_wall";
    s.closed = false;
    s.mesh = inguinal::make_grid_sheet(
        wall, [kind](Real x, Real y) { return tapp_wall_height(x, y) - dimple(kind, x, y); }, border);
    for (const auto& side : border) s.fixed.insert(s.fixed.end(), side.begin(), side.end());
    std::sort(s.fixed.begin(), s.fixed.end());
    s.fixed.erase(std::unique(s.fixed.begin(), s.fixed.end()), s.fixed.end());
    // Muscle and transversalis fascia: firm, held by its border and home springs.
    s.material_preset = "abdominal_wall";
    s.material = {{"mass", 0}, {"sheet_thickness", 0.01}, {"k_home", 50}};
    s.graspable = false;  // jaws closing on a mesh laid on it take the mesh, not a bite of the wall
    s.colour = kMuscle.colour;
    s.opacity = kMuscle.opacity;
    out.structures.push_back(std::move(s));
  }
  // --- The peritoneum still on the wall above the incision (1 mm in front of it).
  {
    inguinal::SheetSpec p;
    p.x0 = kWallX0;
    p.y0 = kIncisionY;
    p.cell = o.cell;
    p.nx = wall.nx;
    p.ny = grid_count(kWallY1 - kIncisionY, o.cell);
    std::vector<std::uint32_t> border[4];
    AnatomyStructure s;
    s.name = "peritoneum";
    s.closed = false;
    s.mesh = inguinal::make_grid_sheet(p, [](Real x, Real y) { return tapp_wall_height(x, y) + 0.001; }, border);
    for (int side : {1, 2, 3}) s.fixed.insert(s.fixed.end(), border[side].begin(), border[side].end());
    std::sort(s.fixed.begin(), s.fixed.end());
    s.fixed.erase(std::unique(s.fixed.begin(), s.fixed.end()), s.fixed.end());
    s.material_preset = "peritoneum";
    s.material = {{"k_home", 5}};
    s.colour = kPeritoneum.colour;
    s.opacity = kPeritoneum.opacity;
    out.structures.push_back(std::move(s));
  }
  // --- The flap: the peritoneum below the incision, dissected off and folded down. It stays
  // attached along the bottom of the field and curls into the cavity (a quarter-turn of radius
  // 8 mm, then straight), 25 mm of it.
  {
    inguinal::SheetSpec f;
    f.x0 = kWallX0;
    f.y0 = 0;
    f.cell = o.cell;
    f.nx = wall.nx;
    f.ny = grid_count(0.025, o.cell);
    std::vector<std::uint32_t> border[4];
    AnatomyStructure s;
    s.name = "peritoneal_flap";
    s.closed = false;
    s.mesh = inguinal::make_grid_sheet(f, [](Real, Real) { return 0.0; }, border);
    constexpr Real kRho = 0.008, kArc = 110 * kDeg;
    for (Vec3& q : s.mesh.positions) {
      const Real arc = q.y();
      Real dy, dz;
      if (arc <= kRho * kArc) {
        dy = -kRho * std::sin(arc / kRho);
        dz = kRho * (1 - std::cos(arc / kRho));
      } else {
        const Real rest = arc - kRho * kArc;
        dy = -kRho * std::sin(kArc) - rest * std::cos(kArc);
        dz = kRho * (1 - std::cos(kArc)) + rest * std::sin(kArc);
      }
      const Real x = q.x();
      q = Vec3(x, kWallY0 + dy, tapp_wall_height(x, kWallY0) + 0.001 + dz);
    }
    s.fixed = border[0];
    s.material_preset = "peritoneum";
    s.material = {{"k_home", 1}};
    s.colour = kFlap.colour;
    s.opacity = kFlap.opacity;
    out.structures.push_back(std::move(s));
  }

  // --- Tubes, bottom layer first.
  TubeLayer tubes(kind, o);
  const std::size_t seg = o.tube_segments;
  // Cooper's ligament (≈ 6 cm on the pecten pubis, Faure et al. 2001) on the superior pubic ramus.
  // The ramus lies behind the wall's surface and the ligament on the surface over it, where the
  // mesh laid on the wall reaches it and a tack fixes the two (the bone standing free in front of
  // the wall held the ligament 2 cm proud, the mesh passing under it out of a tack's reach).
  const Vec2 cooper0(-0.014, -0.020), cooper1(0.045, -0.011);
  const Vec2 cooper_dir = (cooper1 - cooper0).normalized();
  const Vec2 caudal(cooper_dir.y(), -cooper_dir.x());
  {
    AnatomyStructure s = tubes.add("pubic_bone", {cooper0 + 0.0085 * caudal - Vec2(0.006, 0), cooper1 + 0.0085 * caudal - 0.004 * cooper_dir},
                                   0.008, kBone, StructureRole::kRigid, /*behind=*/true);
    s.material_preset.clear();
    out.structures.push_back(std::move(s));
  }
  {
    AnatomyStructure s = tubes.add("coopers_ligament", {cooper0, cooper1}, 0.0025, kLigament, StructureRole::kTissue);
    // A fascial band on bone: every vertex fixed (it never moves), but a tissue, so that a tack
    // can fix the mesh to its surface.
    s.material_preset = "soft";
    for (std::uint32_t v = 0; v < s.mesh.vertex_count(); ++v) s.fixed.push_back(v);
    out.structures.push_back(std::move(s));
  }
  // External iliac vein (Ø 12 mm) medial to the artery (Ø 9 mm): they run up from the pelvis and
  // pass under the IPT just below the deep ring.
  const Vec2 eia0(0.083, kWallY0), eia1(0.062, 0.008);
  const Vec2 eiv0(0.0705, kWallY0), eiv1(0.0495, 0.008);
  {
    AnatomyStructure s = tubes.add("external_iliac_vein", {eiv0, eiv1}, 0.006, kVein, StructureRole::kTissue);
    vessel_material(s, seg);
    s.vessel_diameter = 2 * s.radius;
    out.structures.push_back(std::move(s));
  }
  {
    AnatomyStructure s = tubes.add("external_iliac_artery", {eia0, eia1}, 0.0045, kArtery, StructureRole::kTissue);
    vessel_material(s, seg);
    s.vessel_diameter = 2 * s.radius;
    s.artery = true;
    out.structures.push_back(std::move(s));
  }
  // Inferior epigastric artery (Ø 2.6 mm) from the iliac artery up the medial side of the deep
  // ring, 4.9 cm from the midline at the ring's level; its two veins 3 mm either side (Ø 2 mm).
  const std::vector<Vec2> iea{{0.060, 0.015}, {0.055, 0.022}, {0.050, 0.029}, {0.049, 0.035},
                              {0.046, 0.045}, {0.041, kIncisionY - 0.003}};
  const auto offset = [&](Real w) {
    std::vector<Vec2> line = iea;
    for (std::size_t i = 0; i < iea.size(); ++i) {
      const Vec2 d = (iea[std::min(i + 1, iea.size() - 1)] - iea[i == 0 ? 0 : i - 1]).normalized();
      line[i] += w * Vec2(-d.y(), d.x());
    }
    line.front() += 0.002 * (line[1] - line[0]).normalized();
    return line;
  };
  for (auto [name, w] : {std::pair{"inferior_epigastric_vein_medial", 0.003}, std::pair{"inferior_epigastric_vein_lateral", -0.003}}) {
    AnatomyStructure s = tubes.add(name, offset(w), 0.001, kVein, StructureRole::kTissue);
    vessel_material(s, seg);
    s.vessel_diameter = 2 * s.radius;
    out.structures.push_back(std::move(s));
  }
  {
    AnatomyStructure s = tubes.add("inferior_epigastric_artery", iea, 0.0013, kArtery, StructureRole::kTissue);
    vessel_material(s, seg);
    s.vessel_diameter = 2 * s.radius;
    s.artery = true;
    out.structures.push_back(std::move(s));
  }
  // The cord at the deep ring: spermatic vessels (a bundle, Ø 4 mm) lateral, the vas (Ø 3 mm)
  // medial, both starting just outside the ring's rim.
  const Real ring_r = direct ? 0.006 : out.defect_radius;
  const Vec2 sp0 = kDeepRing + (ring_r + 0.004) * kSpermaticDir;
  {
    AnatomyStructure s = tubes.add("spermatic_vessels", {sp0, kDeepRing + 0.045 * kSpermaticDir, Vec2(0.092, kWallY0)},
                                   0.002, kSpermatic, StructureRole::kTissue);
    vessel_material(s, seg);
    s.vessel_diameter = 0.0015;  // the pampiniform plexus' veins in the bundle (the bundle is Ø 4 mm)
    out.structures.push_back(std::move(s));
  }
  const Vec2 vas0 = kDeepRing + (ring_r + 0.0035) * kVasDir;
  {
    AnatomyStructure s = tubes.add("vas_deferens", {vas0, kDeepRing + 0.030 * kVasDir, Vec2(0.046, -0.004)}, 0.0015,
                                   kVas, StructureRole::kTissue);
    vessel_material(s, seg);
    out.structures.push_back(std::move(s));
  }
  // The medial umbilical fold (the obliterated umbilical artery), medial to Hesselbach's triangle.
  {
    AnatomyStructure s = tubes.add("medial_umbilical_fold", {{0.012, -0.002}, {0.010, 0.020}, {0.006, kIncisionY - 0.003}},
                                   0.0025, kFold, StructureRole::kTissue);
    vessel_material(s, seg);
    out.structures.push_back(std::move(s));
  }

  // --- The hernia sac in the defect.
  const Vec3 centre = on_wall(defect);
  const Vec3 n = tapp_wall_normal(defect.x(), defect.y());
  const Vec3 e1 = (Vec3::UnitX() - Vec3::UnitX().dot(n) * n).normalized();
  {
    // Indirect: a finger along the inguinal canal (medial and caudal, toward the tubercle);
    // direct: a dome straight out through the floor.
    Vec3 axis = -n;
    if (!direct) {
      const Vec2 canal = (kPubicTubercle - kAsis).normalized();
      Vec3 along(canal.x(), canal.y(), 0);
      along -= along.dot(n) * n;
      axis = (-n + 0.5 * along.normalized()).normalized();
    }
    AnatomyStructure s;
    s.name = "hernia_sac";
    std::vector<std::uint32_t> neck;
    s.mesh = inguinal::make_sac(centre, n, e1, axis, out.defect_radius - 0.001, 0.004, sac_length, o.sac_segments,
                                o.sac_rings, neck);
    if (o.sac_neck_fixed) s.fixed = neck;
    s.material_preset = "soft";
    s.material = {{"k_home", o.sac_k_home}, {"home_yield", o.sac_home_yield}};
    s.colour = kSac.colour;
    s.opacity = kSac.opacity;
    out.structures.push_back(std::move(s));
  }

  // --- Zones.
  const Vec2 apex = kDeepRing + Vec2(0, -(ring_r + 0.002));
  const auto leg_to_bottom = [&](const Vec2& dir) { return apex + ((apex.y() - (kWallY0 + 0.005)) / -dir.y()) * dir; };
  out.zones.push_back(zone_on_wall("triangle_of_doom", {apex, leg_to_bottom(kVasDir), leg_to_bottom(kSpermaticDir)},
                                   0.006, 0.010));
  {
    const Vec2 bottom = leg_to_bottom(kSpermaticDir) + Vec2(0.004, 0);
    out.zones.push_back(zone_on_wall("triangle_of_pain",
                                     {Vec2(0.070, 0.024), bottom, Vec2(0.125, kWallY0 + 0.005), Vec2(0.125, 0.055)},
                                     0.003, 0.008));
  }
  out.zones.push_back(zone_on_wall("epigastric_vessels", strip(iea, 0.007), 0.002, 0.008));
  {
    const Vec2 d = (eia1 - eia0).normalized();
    const Vec2 lateral(d.y(), -d.x());
    out.zones.push_back(zone_on_wall("iliac_vessels",
                                     {eiv0 - 0.008 * lateral - 0.004 * d, eia0 + 0.008 * lateral - 0.004 * d, eia1 + 0.008 * lateral + 0.004 * d,
                                      eiv1 - 0.008 * lateral + 0.004 * d},
                                     0.006, 0.010));
  }

  // --- Landmarks.
  auto& L = out.landmarks;
  L["defect_centre"] = centre;
  L["wall_point"] = centre;
  L["wall_normal"] = n;
  L["deep_ring"] = on_wall(kDeepRing);
  L["pubic_tubercle"] = on_wall(kPubicTubercle);
  L["asis"] = on_wall(kAsis);
  // The myopectineal orifice, 7.8 × 6.5 cm (Wolloscheck & Konerding 2009): rectus border to
  // iliopsoas, Cooper's ligament to the transversus arch.
  L["mpo_min"] = on_wall({0.022, -0.005});
  L["mpo_max"] = on_wall({0.100, 0.060});
  L["mpo_0"] = on_wall({0.022, -0.005});
  L["mpo_1"] = on_wall({0.100, -0.005});
  L["mpo_2"] = on_wall({0.100, 0.060});
  L["mpo_3"] = on_wall({0.022, 0.060});
  {
    const AnatomyStructure* cooper = out.find("coopers_ligament");
    const Vec3 mid = cooper->centreline[cooper->centreline.size() / 2];
    L["tack_cooper"] = mid + cooper->radius * tapp_wall_normal(mid.x(), mid.y());
  }
  L["tack_medial"] = on_wall({0.020, 0.040});
  L["tack_lateral"] = on_wall({0.100, 0.058});
  L["tack_superior"] = on_wall({0.075, 0.055});
  // Ports (Sherwinter 2020; artofsurgery.net): the camera at the umbilicus, 5 mm working ports at
  // its level lateral to the rectus, the contralateral one 2.5 cm lower.
  L["camera_port"] = Vec3(0.0, 0.130, 0.060);
  L["port_right"] = Vec3(0.070, 0.130, 0.050);
  L["port_left"] = Vec3(-0.070, 0.105, 0.050);
  L["mesh_start"] = on_wall({0.060, 0.072}, 0.015);
  return out;
}

}  // namespace trocar

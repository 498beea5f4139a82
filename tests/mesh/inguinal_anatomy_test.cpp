// The generated TAPP groin (mesh/inguinal_anatomy.h): clean meshes, true scale against the
// published figures (docs/anatomy.md), zones over the structures they name, the sac through the
// wall at the defect, no two tubes overlapping.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "trocar/core/error.h"
#include "trocar/mesh/inguinal_anatomy.h"
#include "trocar/mesh/validate.h"

namespace trocar {
namespace {

constexpr HerniaKind kKinds[] = {HerniaKind::kIndirect, HerniaKind::kDirect};

const AnatomyStructure& get(const InguinalAnatomy& a, const std::string& name) {
  const AnatomyStructure* s = a.find(name);
  if (s == nullptr) throw Error("no structure " + name);
  return *s;
}

/// x of a centreline where it crosses height y (linear between samples), NaN if it does not.
Real x_at_y(const std::vector<Vec3>& line, Real y) {
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Real y0 = line[i].y(), y1 = line[i + 1].y();
    if ((y0 - y) * (y1 - y) <= 0 && y0 != y1) return line[i].x() + (y - y0) / (y1 - y0) * (line[i + 1].x() - line[i].x());
  }
  return std::nan("");
}

Real segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  // Sampled: fine enough at the 1 mm scale of the tubes' clearance.
  Real best = 1e9;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j)
      best = std::min(best, ((p0 + (p1 - p0) * (i / 20.0)) - (q0 + (q1 - q0) * (j / 20.0))).norm());
  return best;
}

TEST(InguinalAnatomy, EveryMeshValidatesAndTheDeformableBudgetHolds) {
  for (HerniaKind kind : kKinds) {
    const InguinalAnatomy a = make_tapp_anatomy(kind);
    std::size_t deformable = 0;
    for (const AnatomyStructure& s : a.structures) {
      const MeshReport r = validate(s.mesh);
      EXPECT_TRUE(s.closed ? r.is_clean() : r.is_clean_open()) << s.name;
      if (s.closed) {
        EXPECT_GT(r.signed_volume, 0) << s.name;
      }
      for (std::uint32_t v : s.fixed) EXPECT_LT(v, s.mesh.vertex_count()) << s.name;
      if (s.role == StructureRole::kTissue) deformable += s.mesh.triangle_count();
    }
    EXPECT_EQ(a.structures.size(), 14u);
    EXPECT_LE(deformable, 6000u) << hernia_kind_name(kind);
    EXPECT_GE(deformable, 3000u);
  }
}

TEST(InguinalAnatomy, VesselDiametersAreTrueScale) {
  const InguinalAnatomy a = make_tapp_anatomy(HerniaKind::kIndirect);
  const auto diameter = [&](const char* name) { return 2 * get(a, name).radius; };
  EXPECT_NEAR(diameter("inferior_epigastric_artery"), 0.0025, 0.0006);  // 1.9–3.0 mm (Petrossian 1994)
  EXPECT_NEAR(diameter("external_iliac_artery"), 0.009, 0.0013);        // ≤ 10.3 mm (Lorbeer 2018)
  EXPECT_NEAR(diameter("external_iliac_vein"), 0.012, 0.0015);          // ≈ 12–13.5 mm
  EXPECT_NEAR(diameter("vas_deferens"), 0.0025, 0.0006);                // 2–3 mm
  // The mesh's rings lie at the radius from the centreline (to the polygon's tolerance).
  const AnatomyStructure& eia = get(a, "external_iliac_artery");
  const Vec3 c = eia.centreline[eia.centreline.size() / 2];
  Real nearest = 1e9;
  for (const Vec3& p : eia.mesh.positions) nearest = std::min(nearest, std::abs((p - c).norm() - eia.radius));
  EXPECT_LT(nearest, 1e-9);
}

TEST(InguinalAnatomy, EpigastricArteryAndDefectsLieWhereTheFactsPutThem) {
  for (HerniaKind kind : kKinds) {
    const InguinalAnatomy a = make_tapp_anatomy(kind);
    const Vec3 ring = a.landmarks.at("deep_ring");
    const Real iea_x = x_at_y(get(a, "inferior_epigastric_artery").centreline, ring.y());
    EXPECT_NEAR(iea_x, 0.052, 0.009);  // 5.17 ± 0.93 cm from the midline
    // The deep ring between 41 % and 51 % of the way from the pubic tubercle to the ASIS.
    const Vec3 pt = a.landmarks.at("pubic_tubercle"), asis = a.landmarks.at("asis");
    const Vec3 axis = asis - pt;
    const Real fraction = (ring - pt).dot(axis) / axis.squaredNorm();
    EXPECT_GE(fraction, 0.41);
    EXPECT_LE(fraction, 0.51);
    const Vec3 defect = a.landmarks.at("defect_centre");
    if (kind == HerniaKind::kIndirect) {
      EXPECT_GT(defect.x(), iea_x + a.defect_radius);  // lateral to the IEA: the deep ring itself
      EXPECT_LT((defect - ring).norm(), 0.006);
    } else {
      EXPECT_LT(defect.x() + a.defect_radius, x_at_y(get(a, "inferior_epigastric_artery").centreline, 0.015));
      EXPECT_GT(defect.y() - a.defect_radius, (defect.x() - pt.x()) * axis.y() / axis.x());  // above the IPT
    }
    EXPECT_GE(2 * a.defect_radius, 0.015);  // EHS 2: 1.5–3 cm
    EXPECT_LE(2 * a.defect_radius, 0.030);
  }
}

TEST(InguinalAnatomy, VasAndSpermaticVesselsMeetAtTheTriangleOfDoomsApex) {
  const InguinalAnatomy a = make_tapp_anatomy(HerniaKind::kIndirect);
  const auto direction = [&](const char* name) {
    const std::vector<Vec3>& c = get(a, name).centreline;
    Vec3 d = c[std::min<std::size_t>(4, c.size() - 1)] - c[0];  // the first ≈ 2.4 cm
    d.z() = 0;
    return d.normalized();
  };
  const Real angle = std::acos(direction("vas_deferens").dot(direction("spermatic_vessels"))) * 180 / 3.14159265358979;
  EXPECT_GE(angle, 34.2);  // 38.6 ± 4.4° (right side, O'Malley et al. 1997)
  EXPECT_LE(angle, 48.0);
  EXPECT_LT(get(a, "vas_deferens").centreline[3].x(), get(a, "spermatic_vessels").centreline[3].x());  // vas medial
}

TEST(InguinalAnatomy, ZonesHoldTheStructuresTheyName) {
  for (HerniaKind kind : kKinds) {
    const InguinalAnatomy a = make_tapp_anatomy(kind);
    const auto zone = [&](const std::string& name) -> const NamedZone& {
      for (const NamedZone& z : a.zones)
        if (z.name == name) return z;
      throw Error("no zone " + name);
    };
    const auto fraction_inside = [&](const char* structure, std::initializer_list<const char*> zones) {
      const std::vector<Vec3>& c = get(a, structure).centreline;
      std::size_t in = 0;
      for (const Vec3& p : c)
        for (const char* z : zones)
          if (zone(z).contains(p)) {
            ++in;
            break;
          }
      return static_cast<Real>(in) / static_cast<Real>(c.size());
    };
    EXPECT_GE(fraction_inside("external_iliac_artery", {"iliac_vessels"}), 0.95);
    EXPECT_GE(fraction_inside("external_iliac_vein", {"iliac_vessels", "triangle_of_doom"}), 0.95);
    EXPECT_GE(fraction_inside("external_iliac_artery", {"triangle_of_doom"}), 0.6);
    EXPECT_GE(fraction_inside("inferior_epigastric_artery", {"epigastric_vessels"}), 0.95);
    EXPECT_GE(fraction_inside("inferior_epigastric_vein_lateral", {"epigastric_vessels"}), 0.95);
    // The tack sites are in no zone; Cooper's ligament is outside the triangle of doom.
    for (const char* site : {"tack_cooper", "tack_medial", "tack_lateral", "tack_superior"})
      EXPECT_EQ(zone_containing(a.zones, a.landmarks.at(site)), nullptr) << site;
    EXPECT_EQ(fraction_inside("coopers_ligament", {"triangle_of_doom"}), 0.0);
    // The triangle of pain lies lateral to the spermatic vessels and below the ASIS.
    const Vec3 pain_point(0.11, 0.0, 0.0);
    const NamedZone& pain = zone("triangle_of_pain");
    EXPECT_TRUE(pain.contains(Vec3(0.11, 0.0, tapp_wall_height(0.11, 0.0))));
    EXPECT_FALSE(pain.contains(Vec3(0.11, 0.0, tapp_wall_height(0.11, 0.0) + 0.05)));  // too far off the wall
    (void)pain_point;
  }
}

TEST(InguinalAnatomy, TheSacPassesThroughTheWallAtTheDefect) {
  for (HerniaKind kind : kKinds) {
    const InguinalAnatomy a = make_tapp_anatomy(kind);
    const AnatomyStructure& sac = get(a, "hernia_sac");
    const Vec3 p = a.landmarks.at("wall_point"), n = a.landmarks.at("wall_normal");
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    EXPECT_GT(n.z(), 0.9);  // into the cavity, toward the camera
    Real below = 0, above = 0;
    for (const Vec3& v : sac.mesh.positions) {
      below = std::min(below, (v - p).dot(n));
      above = std::max(above, (v - p).dot(n));
    }
    EXPECT_LT(below, -0.02) << "protrudes out of the cavity";
    EXPECT_GT(above, 0.002) << "its neck cap in the cavity";
    // The neck: fixed vertices in the wall's plane, inside the defect.
    ASSERT_FALSE(sac.fixed.empty());
    for (std::uint32_t v : sac.fixed) {
      const Vec3 q = sac.mesh.positions[v];
      EXPECT_NEAR((q - p).dot(n), 0, 1e-9);
      EXPECT_LT((q - p).norm(), a.defect_radius);
    }
    // Its volume: about the half-ellipsoid's (2/3)·π·r²·L plus the cap.
    EXPECT_GT(sac.mesh.signed_volume(), 0.5 * (2.0 / 3.0) * 3.14159 * std::pow(a.defect_radius - 0.001, 2) * 0.025);
  }
}

TEST(InguinalAnatomy, NoTwoTubesOverlap) {
  for (HerniaKind kind : kKinds) {
    const InguinalAnatomy a = make_tapp_anatomy(kind);
    std::vector<const AnatomyStructure*> tubes;
    for (const AnatomyStructure& s : a.structures)
      if (s.radius > 0) tubes.push_back(&s);
    ASSERT_EQ(tubes.size(), 10u);
    for (std::size_t i = 0; i < tubes.size(); ++i)
      for (std::size_t j = i + 1; j < tubes.size(); ++j) {
        const AnatomyStructure& s = *tubes[i];
        const AnatomyStructure& t = *tubes[j];
        Real d = 1e9;
        for (std::size_t p = 0; p + 1 < s.centreline.size(); ++p)
          for (std::size_t q = 0; q + 1 < t.centreline.size(); ++q) {
            if ((s.centreline[p] - t.centreline[q]).norm() > 0.03) continue;
            d = std::min(d, segment_distance(s.centreline[p], s.centreline[p + 1], t.centreline[q], t.centreline[q + 1]));
          }
        EXPECT_GE(d, s.radius + t.radius) << s.name << " / " << t.name;
      }
    // Every tube lies on the cavity side of the wall but the pubic ramus, behind it under Cooper's
    // ligament (the ligament on the surface, where the mesh laid on the wall meets it).
    for (const AnatomyStructure* s : tubes)
      for (const Vec3& c : s->centreline) {
        const Real above = c.z() - tapp_wall_height(c.x(), c.y());
        if (s->name == "pubic_bone")
          EXPECT_LE(above, -s->radius) << s->name;
        else
          EXPECT_GE(above, s->radius) << s->name;
      }
  }
}

TEST(InguinalAnatomy, LandmarksAndMpoSize) {
  const InguinalAnatomy a = make_tapp_anatomy(HerniaKind::kIndirect);
  for (const char* name : {"defect_centre", "wall_point", "wall_normal", "mpo_min", "mpo_max", "tack_cooper", "tack_medial",
                           "tack_lateral", "tack_superior", "camera_port", "port_left", "port_right", "mesh_start"})
    EXPECT_EQ(a.landmarks.count(name), 1u) << name;
  const Vec3 size = a.landmarks.at("mpo_max") - a.landmarks.at("mpo_min");
  EXPECT_NEAR(size.x(), 0.078, 0.005);  // 7.8 × 6.5 cm (Wolloscheck & Konerding 2009)
  EXPECT_NEAR(size.y(), 0.065, 0.005);
  const Vec3 cam = a.landmarks.at("camera_port"), right = a.landmarks.at("port_right");
  EXPECT_NEAR(right.x() - cam.x(), 0.07, 0.005);  // ipsilateral port ≈ 7 cm lateral
}

TEST(InguinalAnatomy, BadOptionsThrow) {
  TappOptions o;
  o.cell = 0.05;
  EXPECT_THROW(make_tapp_anatomy(HerniaKind::kDirect, o), Error);
  o = {};
  o.sac_segments = 10;
  EXPECT_THROW(make_tapp_anatomy(HerniaKind::kDirect, o), Error);
  o = {};
  o.defect_diameter = 0.05;
  EXPECT_THROW(make_tapp_anatomy(HerniaKind::kIndirect, o), Error);
  EXPECT_THROW(make_tube({Vec3::Zero()}, 0.001, 8), Error);
}

TEST(InguinalAnatomy, CoarserAndFinerResolutionsStayClean) {
  for (Real cell : {0.004, 0.0075}) {
    TappOptions o;
    o.cell = cell;
    o.tube_segments = 8;
    const InguinalAnatomy a = make_tapp_anatomy(HerniaKind::kIndirect, o);
    for (const AnatomyStructure& s : a.structures) {
      const MeshReport r = validate(s.mesh);
      EXPECT_TRUE(s.closed ? r.is_clean() : r.is_clean_open()) << s.name << " cell " << cell;
    }
  }
}

}  // namespace
}  // namespace trocar

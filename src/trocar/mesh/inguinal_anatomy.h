#pragma once
/// The right groin of a TAPP (transabdominal preperitoneal) hernia repair, generated in code at
/// true scale (metres), with the peritoneal flap already opened, as a laparoscope at the umbilicus
/// sees it. Plain data: structures (meshes with their role, material and look), named danger
/// zones and named landmarks. docs/anatomy.md gives the frame, every size and its source.
///
/// Frame (right-handed, metres): x medial → lateral (0 on the midline, the patient's right is +x),
/// y caudal → cranial (0 at the level of the pubic tubercle), z normal to the groin's wall into the
/// abdominal cavity (toward the camera). The wall's inner surface is z = wall_height(x, y).
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/geometry/zone.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// Which hernia the groin holds (EHS classification, Miserez et al. 2007).
enum class HerniaKind {
  kIndirect,  ///< L: the sac through the deep ring, lateral to the inferior epigastric vessels
  kDirect,    ///< M: the sac through Hesselbach's triangle, medial to them
};

/// "indirect" / "direct".
const char* hernia_kind_name(HerniaKind kind);

/// Resolution and the few free parameters. Defaults keep the deformable total under 6000 triangles.
struct TappOptions {
  Real cell = 0.005;                 ///< wall, peritoneum and flap grid spacing (m)
  std::size_t tube_segments = 10;    ///< vertices round each vessel / cord (≥ 3)
  Real tube_spacing = 0.006;         ///< ring spacing along each tube (m)
  std::size_t sac_segments = 16;     ///< vertices round the hernia sac (multiple of 4, ≥ 8)
  std::size_t sac_rings = 10;        ///< rings along the sac's outer part (≥ 2)
  Real defect_diameter = 0;          ///< m; 0: the kind's default (indirect 20 mm, direct 22 mm: EHS 2)
  Real sac_length = 0;               ///< m, how far the sac protrudes; 0: indirect 40 mm, direct 25 mm
  Real sac_k_home = 0.5;             ///< N/m, the sac's home springs (holds it against gravity)
  /// m, the sac's home springs' yield (MassSpringMaterial::home_yield; 0: elastic): with a free
  /// neck, a sac drawn back further than this stays back, within it of where it was let go.
  Real sac_home_yield = 0;
  /// The sac's neck ring fixed in the wall's plane (true), or free and held by the home springs
  /// alone (false: the sac with its contents is a closed body that slides back through the defect).
  bool sac_neck_fixed = true;
};

/// How a structure behaves in the simulation.
enum class StructureRole {
  kTissue,  ///< deformable (a tissue), held by its fixed vertices and home springs
  kRigid,   ///< never moves (a rigid obstacle)
};

/// One structure of the groin.
struct AnatomyStructure {
  std::string name;                      ///< e.g. "inferior_epigastric_artery"
  TriMesh mesh;                          ///< world positions (m)
  StructureRole role = StructureRole::kTissue;
  bool closed = true;                    ///< closed and outward (validates clean), else an open sheet (clean_open)
  /// The tissue's material: a preset of tissue/material.h and overrides by their scene key
  /// ("k_home", "sheet_thickness", ...; docs/scene.md). Unused for rigids.
  std::string material_preset = "soft";
  std::vector<std::pair<std::string, Real>> material;
  std::vector<std::uint32_t> fixed;      ///< vertex indices (this mesh's order) that never move
  bool graspable = true;                 ///< jaws may hold it (TissueBody::graspable)
  std::array<float, 3> colour{0.8f, 0.4f, 0.4f};  ///< linear RGB
  float opacity = 1.0f;
  /// A blood vessel (it bleeds when cut, torn or burnt through; docs/electrosurgery.md): the
  /// lumen's diameter (m; 0: not a vessel) and whether it is an artery.
  Real vessel_diameter = 0;
  bool artery = false;
  /// Tubes: the centreline (m) and radius the mesh was built on (empty / 0 for other shapes).
  std::vector<Vec3> centreline;
  Real radius = 0;
};

/// The whole groin.
struct InguinalAnatomy {
  HerniaKind kind = HerniaKind::kIndirect;
  std::vector<AnatomyStructure> structures;
  std::vector<NamedZone> zones;
  /// Named points (m) and one direction, "wall_normal" (unit, into the cavity). docs/anatomy.md
  /// lists them.
  std::map<std::string, Vec3> landmarks;
  Real defect_radius = 0;                ///< m

  /// The structure called `name`, or nullptr.
  const AnatomyStructure* find(const std::string& name) const;
};

/// Builds the groin. Throws trocar::Error on bad options.
InguinalAnatomy make_tapp_anatomy(HerniaKind kind, const TappOptions& options = {});

/// The wall's inner surface height z(x, y) (m), without the deep ring's dimple, and its unit
/// normal into the cavity.
Real tapp_wall_height(Real x, Real y);
Vec3 tapp_wall_normal(Real x, Real y);

/// A closed tube of `radius` along a centreline (≥ 2 points, consecutive points distinct):
/// one ring of `segments` vertices at each point (frames by parallel transport), flat capped
/// ends with a centre vertex. V = n·s + 2, T = 2·s·(n − 1) + 2·s; outward, validates clean when
/// the centreline bends gently (radius of curvature > radius).
TriMesh make_tube(const std::vector<Vec3>& centreline, Real radius, std::size_t segments);

/// A polyline through `points`, smoothed (centripetal-free uniform Catmull–Rom) and resampled at
/// about `spacing` (m): the first and last points are kept.
std::vector<Vec3> smooth_polyline(const std::vector<Vec3>& points, Real spacing);

}  // namespace trocar

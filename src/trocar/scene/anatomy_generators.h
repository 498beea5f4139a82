#pragma once
/// Scene generators for the procedural anatomy and instruments (trocar/mesh/anatomy.h,
/// trocar/mesh/instruments.h), as rows of the mesh_generators() table. Every key is checked;
/// lengths in metres.
#include "trocar/mesh/tri_mesh.h"
#include "trocar/scene/json_reader.h"

namespace trocar {

/// "hernia-peritoneum": width, height, sac_radius, sac_depth (m, required); segments (multiple
/// of 4, default 32), sac_rings (default 6), sheet_rings (default 8).
TriMesh generate_hernia_peritoneum(const JsonReader& spec);
/// "abdominal-wall": width, height, hole_radius (m, required); thickness (m, default 0: an open
/// sheet); segments (multiple of 4, default 32), rings (default 6).
TriMesh generate_abdominal_wall(const JsonReader& spec);
/// "liver-lobe": length, width, thickness (m, required); subdivisions (0..6, default 3),
/// flatten (default 0.5), taper (default 0.3).
TriMesh generate_liver_lobe(const JsonReader& spec);
/// "grasper": all optional, defaults of GrasperSize: shaft_radius, shaft_length, jaw_length,
/// jaw_width, jaw_thickness, jaw_gap (m), segments. Jaw triangles are 0..23.
TriMesh generate_grasper(const JsonReader& spec);
/// "hook-probe": all optional, defaults of HookSize: shaft_radius, shaft_length, hook_radius,
/// stem_length, hook_length (m), segments.
TriMesh generate_hook_probe(const JsonReader& spec);
/// "tacker": all optional, defaults of TackerSize: shaft_radius, shaft_length, bevel (m), segments.
TriMesh generate_tacker(const JsonReader& spec);
/// "suction-irrigator": all optional, defaults of SuctionIrrigatorSize: shaft_radius,
/// shaft_length, tip_round (m), round_rings, segments.
TriMesh generate_suction_irrigator(const JsonReader& spec);

}  // namespace trocar

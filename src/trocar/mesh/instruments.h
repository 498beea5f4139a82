#pragma once
/// Procedural laparoscopic instruments in metres for the shipped scenes. Convention for every
/// instrument here: the working tip is at the mesh origin and the shaft runs from it along +z
/// (tip → handle = +z), so a scene keyframe's `position` places the tip and the top vertex
/// (`auto`) is the handle end's cap centre. Every component is closed and outward.
#include <cstdint>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// A mesh plus the triangles of its grasping surfaces (empty for instruments without jaws).
struct InstrumentMesh {
  TriMesh mesh;                             ///< local frame, metres, tip at the origin
  std::vector<std::uint32_t> jaw_triangles;  ///< indices into mesh.triangles
  Vec3 tip = Vec3::Zero();                  ///< the working tip (local, m): where a tack leaves
  Vec3 tip_axis = -Vec3::UnitZ();           ///< unit, the way the tip points (away from the handle)
};

/// Sizes of make_grasper() (metres). Defaults: a 5 mm laparoscopic grasper.
struct GrasperSize {
  Real shaft_radius = 0.0025;  ///< Ø5 mm shaft
  Real shaft_length = 0.30;    ///< 30 cm shaft
  Real jaw_length = 0.020;     ///< 20 mm jaws
  Real jaw_width = 0.003;      ///< across the jaw (x) at its base; 2/3 of it at the tip
  Real jaw_thickness = 0.0015; ///< each jaw (y) at its base; 2/3 of it at the tip
  Real jaw_gap = 0.002;        ///< between the two grasping faces (y), the jaws' open state
  std::size_t segments = 16;   ///< around the shaft (≥ 3)
};

/// A grasper: two jaws, tapered boxes z ∈ [0, jaw_length] on either side of the plane y = 0
/// (grasping faces at y = ±jaw_gap/2), and a capped cylinder shaft z ∈ [jaw_length,
/// jaw_length + shaft_length]. Three closed components: V = 16 + 2s + 2, T = 24 + 4s.
/// jaw_triangles = all 24 triangles of both jaws (the jaws grasp whatever they touch when
/// closed; the mesh does not move with the jaw closure). Throws trocar::Error on bad sizes.
InstrumentMesh make_grasper(const GrasperSize& size = {});

/// Sizes of make_hook_probe() (metres). Defaults: a Ø4.5 mm hook electrode.
struct HookSize {
  Real shaft_radius = 0.00225;  ///< Ø4.5 mm shaft
  Real shaft_length = 0.30;     ///< 30 cm shaft
  Real hook_radius = 0.0006;    ///< the wire of the hook
  Real stem_length = 0.010;     ///< the straight wire from the elbow up to the shaft
  Real hook_length = 0.005;     ///< the foot of the L, along +x from the elbow
  std::size_t segments = 12;    ///< around the wire and the shaft (≥ 3)
};

/// A hook probe: one closed tube swept along an L (foot along +x, elbow, stem along +z, a flat
/// step up to the shaft radius at z = stem_length, shaft up to stem_length + shaft_length, cap).
/// The foot's axis is at z = hook_radius, so the elbow's outer bottom touches z = 0: the origin
/// is the tip, directly below the elbow on the shaft axis. Rings: foot end, elbow (mitred at 45°),
/// stem top, shaft bottom, shaft top, plus two cap centres: V = 5s + 2, T = 10s, χ = 2.
InstrumentMesh make_hook_probe(const HookSize& size = {});

/// Sizes of make_tacker() (metres). Defaults: a 5 mm helical-tack applier (ProTack-like:
/// Ø5 mm, about 33 cm of shaft; Covidien ProTack instructions for use).
struct TackerSize {
  Real shaft_radius = 0.0025;  ///< Ø5 mm shaft
  Real shaft_length = 0.33;    ///< tip to handle end
  Real bevel = 0.001;          ///< the blunt tip's chamfer: its length along z and its inset in radius
  std::size_t segments = 16;   ///< around the shaft (≥ 3)
};

/// A tacker: one closed capped cylinder z ∈ [0, shaft_length] whose tip end is blunt, a flat disc
/// of radius shaft_radius − bevel at z = 0 chamfered out to the full radius at z = bevel. Rings:
/// tip disc, chamfer top, handle end, plus two cap centres: V = 3s + 2, T = 6s, χ = 2.
/// tip = the origin, tip_axis = −z (a tack leaves along it). Throws trocar::Error on bad sizes.
InstrumentMesh make_tacker(const TackerSize& size = {});

/// Sizes of make_suction_irrigator() (metres). Defaults: a 5 mm suction-irrigation cannula (Ø5 mm,
/// 33 cm, the common laparoscopic length; its side holes and bore are not modelled).
struct SuctionIrrigatorSize {
  Real shaft_radius = 0.0025;  ///< Ø5 mm shaft
  Real shaft_length = 0.33;    ///< tip to handle end
  Real tip_round = 0.001;      ///< the blunt tip's rounded edge: a quarter circle of this radius
  std::size_t round_rings = 3; ///< rings along that quarter circle (≥ 1; 1 is the tacker's chamfer)
  std::size_t segments = 16;   ///< around the shaft (≥ 3)
};

/// A suction-irrigator: one closed capped cylinder z ∈ [0, shaft_length] whose tip end is a flat
/// disc of radius shaft_radius − tip_round at z = 0, rounded out to the full radius at z =
/// tip_round. Rings: tip disc, round_rings along the rounding (n), handle end, plus two cap
/// centres: V = (n + 2)s + 2, T = 2(n + 2)s, χ = 2. tip = the origin, tip_axis = −z (where it
/// draws in and the way its jet leaves). Throws trocar::Error on bad sizes.
InstrumentMesh make_suction_irrigator(const SuctionIrrigatorSize& size = {});

}  // namespace trocar

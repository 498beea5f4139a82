#pragma once
/// The prosthetic (polypropylene) mesh of a hernia repair as a triangulated sheet, and its rolled
/// form for introduction through a port (docs/response.md, "Tissue against tissue").
#include <span>

#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// An open rectangular sheet in the plane z = 0, centred at the origin, x ∈ [−w/2, w/2],
/// y ∈ [−h/2, h/2], on a square grid of about `spacing` (the cell count per side is
/// round(size/spacing), at least 1), cells split along alternating diagonals, wound
/// counter-clockwise seen from +z. Texture coordinates per corner are the corner's (x + w/2,
/// y + h/2) in metres, so a weave texture is tiled by scaling them by its repeats per metre.
/// Validates clean_open. Throws trocar::Error for a non-positive or non-finite size or spacing,
/// or more than 10⁶ vertices.
TriMesh make_prosthetic_mesh(Real width, Real height, Real spacing);

/// How a flat sheet is rolled up (scene key "roll").
struct SheetRoll {
  int axis = 0;          ///< 0: the roll's axis is parallel to x (the sheet rolls along y); 1: to y
  Real radius = 0.004;   ///< radius of the innermost turn (m)
  Real gap = 0.002;      ///< distance between successive turns (m), > the contact thickness
};

/// Maps the positions of a flat sheet lying in a plane z = const onto an Archimedean spiral
/// r(θ) = radius + gap·θ/2π about a line parallel to the roll's axis, by arc length: the sheet's
/// coordinate across the axis becomes the arc length along the spiral, the coordinate along the
/// axis is kept. Lengths along the axis are exact; lengths across it become arcs of the same
/// length (a chord of length l on a turn of radius r is shorter by about l³/24r²). The edge at
/// the smallest coordinate is the innermost turn; the outermost end lies at the bottom, and the
/// roll rests on the sheet's former plane, centred where the sheet was. Throws trocar::Error for
/// a non-flat input (z spread > 1e-6 of its size), radius or gap ≤ 0, or an axis other than 0, 1.
void roll_sheet(std::span<Vec3> positions, const SheetRoll& roll);

}  // namespace trocar

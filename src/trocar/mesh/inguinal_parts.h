#pragma once
/// Shape builders behind make_tapp_anatomy (inguinal_anatomy.h): a wall grid with a round hole,
/// the folded peritoneal flap and the hernia sac. Internal to the mesh module.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar::inguinal {

/// z(x, y) of a sheet's vertices.
using HeightField = std::function<Real(Real, Real)>;

/// A grid sheet with its corner at (x0, y0), nx × ny cells of `cell` (m), counter-clockwise seen
/// from +z, heights from `height`. With hole_m > 0, the (2·hole_m)² cells round grid node
/// (hole_i, hole_j) are replaced by an annulus of `hole_rings` bands from a circle of `hole_r`
/// (m, < hole_m·cell) to the square's border (the border nodes shared, so it is one welded sheet).
/// `border` receives the outer border's vertices, by side: [0] y = y0, [1] x = x_max,
/// [2] y = y_max, [3] x = x0 (corners in two lists).
struct SheetSpec {
  Real x0 = 0, y0 = 0, cell = 0.005;
  std::size_t nx = 1, ny = 1;
  std::size_t hole_i = 0, hole_j = 0, hole_m = 0, hole_rings = 2;
  Real hole_r = 0;
};
TriMesh make_grid_sheet(const SheetSpec& spec, const HeightField& height,
                        std::vector<std::uint32_t> (&border)[4]);

/// The hernia sac, a closed body of revolution round the defect's centre `centre` on the wall,
/// `normal` the wall's unit normal into the cavity, `e1` a unit vector in the wall's plane:
/// a low dome (height `cap`) on the cavity side, the neck ring (radius `neck_r`) in the wall's
/// plane, and a half-ellipsoid protruding `length` out of the cavity along `axis` (unit, with
/// axis·normal < 0; rings stay parallel to the wall, their centres move along the axis).
/// `neck` receives the neck ring's vertices. Outward, validates clean.
TriMesh make_sac(const Vec3& centre, const Vec3& normal, const Vec3& e1, const Vec3& axis, Real neck_r, Real cap,
                 Real length, std::size_t segments, std::size_t rings, std::vector<std::uint32_t>& neck);

}  // namespace trocar::inguinal

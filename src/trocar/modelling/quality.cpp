#include "trocar/modelling/quality.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStaticCellLocator.h>

#include "trocar/mesh/validate.h"

namespace trocar {
namespace {

vtkNew<vtkPolyData> to_poly(const TriMesh& mesh) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(mesh.positions.size()));
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    points->SetPoint(static_cast<vtkIdType>(i), mesh.positions[i].data());
  }
  vtkNew<vtkCellArray> cells;
  for (const Triangle& t : mesh.triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    cells->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetPolys(cells);
  return poly;
}

/// Σ and max of the distances from `from`'s vertices to `to`'s surface.
void one_way(const TriMesh& from, const TriMesh& to, Real& sum, Real& max) {
  vtkNew<vtkPolyData> poly = to_poly(to);
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(poly);
  locator->BuildLocator();
  double closest[3];
  vtkIdType cell = 0;
  int sub = 0;
  double d2 = 0;
  for (const Vec3& p : from.positions) {
    locator->FindClosestPoint(p.data(), closest, cell, sub, d2);
    const Real d = std::sqrt(d2);
    sum += d;
    max = std::max(max, d);
  }
}

}  // namespace

SurfaceDistance surface_distance(const TriMesh& a, const TriMesh& b) {
  SurfaceDistance out;
  if (a.empty() || b.empty()) return out;
  Real sum = 0;
  one_way(a, b, sum, out.max);
  one_way(b, a, sum, out.max);
  out.mean = sum / static_cast<Real>(a.positions.size() + b.positions.size());
  return out;
}

ShapeQuality shape_quality(const TriMesh& mesh) {
  ShapeQuality q;
  q.min_angle_deg = 180;
  Real sum_min = 0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const auto c = mesh.corners(t);
    const Real l[3] = {(c[1] - c[2]).norm(), (c[2] - c[0]).norm(), (c[0] - c[1]).norm()};
    const Real area = 0.5 * (c[1] - c[0]).cross(c[2] - c[0]).norm();
    Real smallest = 180;
    for (int k = 0; k < 3; ++k) {
      // Angle opposite edge k by the law of cosines.
      const Real b = l[(k + 1) % 3], cc = l[(k + 2) % 3];
      const Real cos_angle = std::clamp((b * b + cc * cc - l[k] * l[k]) / (2 * b * cc), -1.0, 1.0);
      smallest = std::min(smallest, std::acos(cos_angle) * 180 / std::numbers::pi);
    }
    if (!std::isfinite(smallest)) smallest = 0;
    q.min_angle_deg = std::min(q.min_angle_deg, smallest);
    sum_min += smallest;
    const Real aspect = area > 0 ? std::max({l[0], l[1], l[2]}) * (l[0] + l[1] + l[2]) / (4 * std::sqrt(3.0) * area)
                                 : std::numeric_limits<Real>::infinity();
    q.max_aspect = std::max(q.max_aspect, aspect);
    std::size_t bin = 0;
    while (bin < kAspectBinEdges.size() && aspect >= kAspectBinEdges[bin]) ++bin;
    ++q.aspect_histogram[bin];
  }
  if (mesh.triangle_count() == 0) q.min_angle_deg = 0;
  q.mean_min_angle_deg = mesh.triangle_count() > 0 ? sum_min / static_cast<Real>(mesh.triangle_count()) : 0;
  return q;
}

int genus(const TriMesh& mesh) {
  const MeshReport r = validate(mesh);
  return (2 * static_cast<int>(r.components) - static_cast<int>(r.euler_characteristic)) / 2;
}

}  // namespace trocar

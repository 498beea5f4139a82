#include "trocar/response/instrument_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace trocar {

InstrumentField::InstrumentField(const TriMesh& local_mesh, Real pad, std::size_t max_cells, Real sample_spacing) {
  if (local_mesh.triangles.empty()) return;
  for (std::uint32_t v = 0; v < local_mesh.positions.size(); ++v) {
    samples_.push_back(local_mesh.positions[v]);
    sample_vertices_.push_back({v, v});
  }
  std::vector<std::array<std::uint32_t, 2>> edges;
  for (const Triangle& t : local_mesh.triangles)
    for (int k = 0; k < 3; ++k) edges.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  if (sample_spacing > 0)
    for (const auto& e : edges) {
      const Vec3& a = local_mesh.positions[e[0]];
      const Vec3& b = local_mesh.positions[e[1]];
      const auto pieces = static_cast<std::size_t>(std::ceil((b - a).norm() / sample_spacing));
      for (std::size_t k = 1; k < pieces; ++k) {
        samples_.push_back(a + (b - a) * (static_cast<Real>(k) / static_cast<Real>(pieces)));
        sample_vertices_.push_back(e);
      }
    }
  exact_.emplace(local_mesh.positions, local_mesh.triangles);
  box_ = Aabb::of_points(local_mesh.positions).inflated(pad);
  const Vec3 size = box_.size();
  // Cubic cells: h³·cells ≈ box volume, rounded up per axis.
  cell_ = std::cbrt(size.prod() / static_cast<Real>(std::max<std::size_t>(max_cells, 1)));
  const auto cells_along = [&](Real extent) {
    return static_cast<std::size_t>(std::max<Real>(1, std::ceil(extent / cell_)));
  };
  while (true) {
    nx_ = cells_along(size.x());
    ny_ = cells_along(size.y());
    nz_ = cells_along(size.z());
    if (nx_ * ny_ * nz_ <= max_cells || max_cells == 0) break;
    cell_ *= 1.05;  // the rounding up overshot: grow the cells a little
  }
  slack_ = cell_ * std::sqrt(Real{3}) / 2;
  values_.resize(nx_ * ny_ * nz_);
  std::uint32_t hint = MeshDistance::kNoTriangle;
  for (std::size_t k = 0; k < nz_; ++k)
    for (std::size_t j = 0; j < ny_; ++j)
      for (std::size_t i = 0; i < nx_; ++i) {
        const Vec3 c = box_.min + cell_ * Vec3(static_cast<Real>(i) + 0.5, static_cast<Real>(j) + 0.5,
                                               static_cast<Real>(k) + 0.5);
        const SignedDistanceResult r = exact_->signed_distance(c, hint);
        hint = r.triangle;
        // Rounded toward −inf so that the float stays a lower bound.
        const Real bound = r.distance - slack_;
        float value = static_cast<float>(bound);
        if (static_cast<Real>(value) > bound) value = std::nextafter(value, -std::numeric_limits<float>::infinity());
        values_[(k * ny_ + j) * nx_ + i] = value;
      }
}

Real InstrumentField::lower_bound(const Vec3& p) const {
  if (values_.empty()) return std::numeric_limits<Real>::infinity();
  const Vec3 u = (p - box_.min) / cell_;
  const Real fx = std::floor(u.x()), fy = std::floor(u.y()), fz = std::floor(u.z());
  const bool in_grid = fx >= 0 && fy >= 0 && fz >= 0 && fx < static_cast<Real>(nx_) &&
                       fy < static_cast<Real>(ny_) && fz < static_cast<Real>(nz_);  // false for NaN
  if (!in_grid) {
    // Outside the box: the mesh lies inside the box, so it is at least as far as the box is
    // (Euclidean distance to the box), which is ≥ 0.
    const Vec3 gap = (box_.min - p).cwiseMax(p - box_.max).cwiseMax(Vec3::Zero());
    return gap.norm();
  }
  const auto i = static_cast<std::size_t>(fx), j = static_cast<std::size_t>(fy), k = static_cast<std::size_t>(fz);
  return values_[(k * ny_ + j) * nx_ + i];
}

}  // namespace trocar

#include "trocar/core/obb.h"

#include <Eigen/Eigenvalues>

namespace trocar {

Obb Obb::fit_pca(std::span<const Vec3> points) {
  Obb box;
  if (points.empty()) return box;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= static_cast<Real>(points.size());
  Mat3 covariance = Mat3::Zero();
  for (const Vec3& p : points) {
    const Vec3 d = p - mean;
    covariance += d * d.transpose();
  }
  // Eigen's solver returns eigenvalues in increasing order; take them largest first.
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(covariance);
  Mat3 axes;
  for (int k = 0; k < 3; ++k) axes.col(k) = solver.eigenvectors().col(2 - k).normalized();
  if (!axes.allFinite()) axes = Mat3::Identity();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);  // keep the frame right-handed

  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity());
  Vec3 hi = -lo;
  for (const Vec3& p : points) {
    const Vec3 local = axes.transpose() * (p - mean);
    lo = lo.cwiseMin(local);
    hi = hi.cwiseMax(local);
  }
  box.axes = axes;
  box.center = mean + axes * (0.5 * (lo + hi));
  box.half_extents = 0.5 * (hi - lo);
  return box;
}

bool Obb::contains(const Vec3& p, Real tolerance) const {
  const Vec3 local = to_local(p);
  return (local.cwiseAbs().array() <= (half_extents.array() + tolerance)).all();
}

std::array<Vec3, 8> Obb::corners() const {
  std::array<Vec3, 8> out;
  for (int i = 0; i < 8; ++i) {
    const Vec3 sign((i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0);
    out[i] = center + axes * sign.cwiseProduct(half_extents);
  }
  return out;
}

Aabb Obb::bounds() const {
  // Half-size of the AABB along world axis i is Σ_k |a_k,i| h_k.
  const Vec3 half = axes.cwiseAbs() * half_extents;
  return {center - half, center + half};
}

}  // namespace trocar

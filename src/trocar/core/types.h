#pragma once
/// Scalar and vector types used everywhere in trocar (SI units, Real = double; docs/architecture.md
/// "Conventions").
#include <array>
#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace trocar {

/// The simulator's scalar: double precision throughout the core.
using Real = double;
/// A point or vector in metres (or whatever unit the caller states), 24 bytes, no alignment needs.
using Vec3 = Eigen::Matrix<Real, 3, 1>;
/// A texture coordinate (u, v).
using Vec2 = Eigen::Matrix<Real, 2, 1>;
/// A 3×3 matrix (rotations, inertia, box axes as columns).
using Mat3 = Eigen::Matrix<Real, 3, 3>;
/// A unit quaternion for rotations.
using Quat = Eigen::Quaternion<Real>;
/// Three vertex indices, counter-clockwise seen from outside (normal = (b−a)×(c−a) points out).
using Triangle = std::array<std::uint32_t, 3>;

}  // namespace trocar

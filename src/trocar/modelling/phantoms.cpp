#include "trocar/modelling/phantoms.h"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "trocar/core/error.h"

namespace trocar {
namespace {

constexpr Real kPi = std::numbers::pi;

std::array<std::size_t, 3> cube_dims(Real half_extent, Real voxel) {
  const auto n = static_cast<std::size_t>(std::ceil(2 * half_extent / voxel)) + 1;
  return {n, n, n};
}

/// Origin that puts the grid's centre at the world origin.
Vec3 centred_origin(const std::array<std::size_t, 3>& dims, Real voxel) {
  return -0.5 * voxel * Vec3(static_cast<Real>(dims[0] - 1), static_cast<Real>(dims[1] - 1), static_cast<Real>(dims[2] - 1));
}

/// Volume of the lens where two spheres of radius r with centres d apart overlap.
Real lens_volume(Real r, Real d) { return d >= 2 * r ? 0 : kPi * (4 * r + d) * (2 * r - d) * (2 * r - d) / 12; }

/// Gives the volume the parts' names, so a phantom in memory can be selected by name.
void name_parts(Phantom& p) {
  for (const Phantom::Part& part : p.parts) p.volume.names[{0, part.label}] = part.name;
}

Real count_volume(const Volume& v, int label) {
  std::size_t n = 0;
  for (float x : v.layers[0]) n += x == static_cast<float>(label) ? 1 : 0;
  return static_cast<Real>(n) * v.voxel_volume();
}

}  // namespace

Volume rasterise(std::array<std::size_t, 3> dims, Real voxel, const Vec3& origin,
                 const std::function<int(const Vec3&)>& label_at) {
  Volume v = make_volume(dims, Vec3::Constant(voxel), origin);
  for (std::size_t k = 0; k < dims[2]; ++k)
    for (std::size_t j = 0; j < dims[1]; ++j)
      for (std::size_t i = 0; i < dims[0]; ++i) {
        const Vec3 p = v.index_to_world(Vec3(static_cast<Real>(i), static_cast<Real>(j), static_cast<Real>(k)));
        v.layers[0][v.index(i, j, k)] = static_cast<float>(label_at(p));
      }
  return v;
}

Phantom sphere_phantom(Real voxel, Real radius) {
  const auto dims = cube_dims(radius + 3 * voxel, voxel);
  Phantom p;
  p.volume = rasterise(dims, voxel, centred_origin(dims, voxel), [radius](const Vec3& x) { return x.norm() <= radius ? 1 : 0; });
  p.volume.source = "sphere phantom";
  p.parts = {{1, "sphere", 4.0 / 3.0 * kPi * radius * radius * radius, 0}};
  name_parts(p);
  return p;
}

Phantom ellipsoid_phantom(Real voxel) {
  const Vec3 semi(0.040, 0.025, 0.015);
  const Mat3 rot = (Eigen::AngleAxis<Real>(0.5, Vec3(0, 0, 1)) * Eigen::AngleAxis<Real>(0.3, Vec3(1, 0, 0))).toRotationMatrix();
  const auto dims = cube_dims(semi.maxCoeff() + 3 * voxel, voxel);
  Phantom p;
  p.volume = rasterise(dims, voxel, centred_origin(dims, voxel), [&](const Vec3& x) {
    const Vec3 local = rot.transpose() * x;
    return local.cwiseQuotient(semi).squaredNorm() <= 1 ? 1 : 0;
  });
  p.volume.source = "ellipsoid phantom";
  p.parts = {{1, "ellipsoid", 4.0 / 3.0 * kPi * semi.prod(), 0}};
  name_parts(p);
  return p;
}

Phantom torus_phantom(Real voxel) {
  const Real major = 0.025, minor = 0.009;
  const auto dims = cube_dims(major + minor + 3 * voxel, voxel);
  Phantom p;
  p.volume = rasterise(dims, voxel, centred_origin(dims, voxel), [&](const Vec3& x) {
    const Real q = std::hypot(x.x(), x.y()) - major;
    return q * q + x.z() * x.z() <= minor * minor ? 1 : 0;
  });
  p.volume.source = "torus phantom";
  p.parts = {{1, "torus", 2 * kPi * kPi * major * minor * minor, 1}};  // Pappus: 2πR · πr²
  name_parts(p);
  return p;
}

Phantom touching_blobs_phantom(Real voxel) {
  const Real r = 0.016, d = 0.026;  // centres 26 mm apart: a 6 mm deep lens in common
  const Vec3 a(-d / 2, 0, 0), b(d / 2, 0, 0);
  const auto dims = std::array<std::size_t, 3>{static_cast<std::size_t>(std::ceil((d + 2 * r) / voxel)) + 7,
                                               static_cast<std::size_t>(std::ceil(2 * r / voxel)) + 7,
                                               static_cast<std::size_t>(std::ceil(2 * r / voxel)) + 7};
  Phantom p;
  p.volume = rasterise(dims, voxel, centred_origin(dims, voxel), [&](const Vec3& x) {
    if ((x - a).norm() <= r) return 1;
    return (x - b).norm() <= r ? 2 : 0;
  });
  p.volume.source = "touching-blobs phantom";
  const Real sphere = 4.0 / 3.0 * kPi * r * r * r;
  p.parts = {{1, "blob-a", sphere, 0}, {2, "blob-b", sphere - lens_volume(r, d), 0}};
  name_parts(p);
  return p;
}

Phantom edge_phantom(Real voxel) {
  const Real r = 0.018;
  const auto n = static_cast<std::size_t>(std::ceil(2 * (r + 3 * voxel) / voxel)) + 1;
  const std::array<std::size_t, 3> dims{n, n, n};
  // The sphere's centre lies 4 voxels above the first slice's centre, so the first slice cuts it.
  const Vec3 origin = centred_origin({n, n, n}, voxel).cwiseProduct(Vec3(1, 1, 0)) + Vec3(0, 0, -4 * voxel);
  Phantom p;
  p.volume = rasterise(dims, voxel, origin, [r](const Vec3& x) { return x.norm() <= r ? 1 : 0; });
  p.volume.source = "edge phantom";
  // Part of the sphere above the plane z = −4.5 voxels (the first voxels' lower face):
  // a sphere less the cap below it, cap height h = r − 4.5·voxel, V_cap = πh²(3r − h)/3.
  const Real h = r - 4.5 * voxel;
  p.parts = {{1, "cut-sphere", 4.0 / 3.0 * kPi * r * r * r - kPi * h * h * (3 * r - h) / 3, 0}};
  name_parts(p);
  return p;
}

Phantom abdomen_phantom(Real voxel) {
  // Liver: a wedge 22 cm long (x), thick and round on the right (x > 0, 14 cm top to bottom)
  // tapering to a thin left lobe (2.4 cm), its cross-sections ellipses whose semi-axes follow a
  // smoothstep along x; the inferior (visceral) face cut flatter than the domed top. The
  // gallbladder: a pear-shaped ellipsoid under the right lobe, its fundus just below the edge.
  const auto smoothstep = [](Real a, Real b, Real x) {
    const Real u = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return u * u * (3 - 2 * u);
  };
  const Real cx = -0.01, sx = 0.11;
  const auto liver = [&](const Vec3& x) {
    const Real t = smoothstep(-0.11, 0.06, x.x());
    const Real sy = 0.050 + 0.035 * t, sz = 0.012 + 0.058 * t;
    const Real q = std::pow((x.x() - cx) / sx, 2) + std::pow(x.y() / sy, 2) + std::pow(x.z() / sz, 2);
    return q <= 1 && x.z() >= -0.6 * sz;
  };
  const Vec3 gall_c(0.035, -0.030, -0.050), gall_s(0.035, 0.014, 0.014);
  const Mat3 gall_rot = Eigen::AngleAxis<Real>(0.5, Vec3(0, 1, 0)).toRotationMatrix();
  const auto gall = [&](const Vec3& x) { return (gall_rot.transpose() * (x - gall_c)).cwiseQuotient(gall_s).norm() <= 1; };
  const std::array<std::size_t, 3> dims{static_cast<std::size_t>(std::ceil(0.25 / voxel)),
                                        static_cast<std::size_t>(std::ceil(0.16 / voxel)),
                                        static_cast<std::size_t>(std::ceil(0.13 / voxel))};
  const Vec3 origin = -0.5 * voxel * Vec3(static_cast<Real>(dims[0] - 1), static_cast<Real>(dims[1] - 1), static_cast<Real>(dims[2] - 1));
  Phantom p;
  p.volume = rasterise(dims, voxel, origin, [&](const Vec3& x) { return liver(x) ? 1 : gall(x) ? 2 : 0; });
  p.volume.source = "abdomen phantom";
  p.parts = {{1, "liver", count_volume(p.volume, 1), 0}, {2, "gallbladder", count_volume(p.volume, 2), 0}};
  name_parts(p);
  return p;
}

const std::vector<std::string>& phantom_names() {
  static const std::vector<std::string> names{"sphere", "ellipsoid", "torus", "touching-blobs", "edge", "abdomen"};
  return names;
}

Phantom make_phantom(const std::string& name, Real voxel) {
  if (!(voxel > 0)) throw Error("phantom voxel size must be > 0");
  if (name == "sphere") return sphere_phantom(voxel);
  if (name == "ellipsoid") return ellipsoid_phantom(voxel);
  if (name == "torus") return torus_phantom(voxel);
  if (name == "touching-blobs") return touching_blobs_phantom(voxel);
  if (name == "edge") return edge_phantom(voxel);
  if (name == "abdomen") return abdomen_phantom(voxel);
  std::string known;
  for (const std::string& n : phantom_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown phantom \"" + name + "\" (known: " + known + ")");
}

}  // namespace trocar

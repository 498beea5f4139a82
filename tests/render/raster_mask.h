#pragma once
// An independent CPU rasteriser for the render tests: projects triangles with a CameraView and
// fills a z-buffered label image (pixel centres at i + 0.5, like OpenGL's rasterisation rule).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "trocar/scene/camera.h"
#include "trocar/sim/view_snapshot.h"
#include "trocar/sim/world.h"

namespace trocar::test {

enum Label : std::uint8_t { kBackground = 0, kTissue = 1, kInstrument = 2, kRigid = 3 };

struct LabelImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> label;
  std::vector<double> depth;
  LabelImage(int w, int h) : width(w), height(h), label(std::size_t(w) * h, kBackground), depth(std::size_t(w) * h, 2.0) {}
  std::uint8_t at(int x, int y) const { return label[std::size_t(y) * width + x]; }

  void triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, std::uint8_t l) {
    if (a.z() < 0 || b.z() < 0 || c.z() < 0) return;  // behind the eye: none in these scenes
    const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (std::abs(area) < 1e-12) return;
    const int x0 = std::max(0, int(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(width - 1, int(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, int(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(height - 1, int(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double w0 = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
        const double w1 = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
        const double w2 = 1 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const double z = w0 * a.z() + w1 * b.z() + w2 * c.z();  // window depth is affine in screen space
        if (z < 0 || z > 1) continue;
        double& d = depth[std::size_t(y) * width + x];
        if (z < d) {
          d = z;
          label[std::size_t(y) * width + x] = l;
        }
      }
  }
};

/// The label image of a snapshot: tissues from the snapshot, instruments from their local
/// meshes carried by the snapshot's poses, rigids from the world.
inline LabelImage project_labels(const World& world, const ViewSnapshot& snap, const CameraView& cam, int w, int h) {
  LabelImage img(w, h);
  const auto draw = [&](const std::vector<Vec3>& x, const std::vector<Triangle>& tris, std::uint8_t l) {
    std::vector<Eigen::Vector3d> p(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) p[i] = cam.project(x[i], w, h);
    for (const Triangle& t : tris) img.triangle(p[t[0]], p[t[1]], p[t[2]], l);
  };
  for (std::size_t t = 0; t < world.tissues.size(); ++t) draw(snap.tissues[t], world.tissues[t]->settings.triangles, kTissue);
  for (std::size_t i = 0; i < world.instruments.size(); ++i) {
    const TriMesh& m = world.instruments[i].instrument.local_mesh();
    std::vector<Vec3> x(m.positions.size());
    for (std::size_t v = 0; v < x.size(); ++v) x[v] = snap.instruments[i].pose.apply(m.positions[v]);
    draw(x, m.triangles, kInstrument);
  }
  for (const RigidBody& r : world.rigids) draw(r.mesh.positions, r.mesh.triangles, kRigid);
  return img;
}

}  // namespace trocar::test

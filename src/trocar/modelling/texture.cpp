#include "trocar/modelling/texture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>

#include "trocar/core/error.h"

namespace trocar {
namespace {

constexpr Real kGutter = 0.03;  // fraction of a chart cell left empty at each side

/// Chart of a normal: 0..5 = +x, −x, +y, −y, +z, −z.
int chart_of(const Vec3& n) {
  int axis = 0;
  n.cwiseAbs().maxCoeff(&axis);
  return 2 * axis + (n[axis] < 0 ? 1 : 0);
}

/// The in-plane axes (u, v) of a chart, chosen so that the chart is seen from outside
/// unmirrored: u × v = the chart's outward axis.
std::array<int, 2> chart_axes(int chart) {
  const int axis = chart / 2;
  return {(axis + 1) % 3, (axis + 2) % 3};
}

Real extent(const TriMesh& mesh) { return std::max(mesh.bounds().size().maxCoeff(), 1e-12); }

// ---- value noise (hash lattice, smooth interpolation), 2-D --------------------------------

Real lattice(std::int64_t x, std::int64_t y, std::uint32_t seed) {
  std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full ^ seed;
  h ^= h >> 31;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 29;
  return static_cast<Real>(h & 0xFFFFFF) / static_cast<Real>(0xFFFFFF);
}

Real value_noise(Real x, Real y, std::uint32_t seed) {
  const Real fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const Real tx = x - fx, ty = y - fy;
  const Real sx = tx * tx * (3 - 2 * tx), sy = ty * ty * (3 - 2 * ty);
  const Real a = lattice(ix, iy, seed), b = lattice(ix + 1, iy, seed);
  const Real c = lattice(ix, iy + 1, seed), d = lattice(ix + 1, iy + 1, seed);
  return (a + (b - a) * sx) + ((c + (d - c) * sx) - (a + (b - a) * sx)) * sy;
}

/// Fractal sum of octaves, in [0, 1].
Real fbm(Real x, Real y, int octaves, std::uint32_t seed) {
  Real sum = 0, amp = 0.5, norm = 0;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * value_noise(x, y, seed + static_cast<std::uint32_t>(o) * 101u);
    norm += amp;
    x *= 2.03;
    y *= 2.03;
    amp *= 0.5;
  }
  return sum / norm;
}

struct Palette {
  Vec3 base, dark, vessel;  ///< RGB in [0, 1]
};

Palette palette_for(const std::string& organ) {
  const auto has = [&organ](const char* word) { return organ.find(word) != std::string::npos; };
  if (has("liver")) return {{0.50, 0.17, 0.12}, {0.33, 0.09, 0.07}, {0.28, 0.10, 0.16}};
  if (has("spleen")) return {{0.45, 0.14, 0.20}, {0.30, 0.08, 0.14}, {0.25, 0.08, 0.20}};
  if (has("kidney")) return {{0.55, 0.22, 0.16}, {0.38, 0.13, 0.10}, {0.30, 0.10, 0.18}};
  if (has("gall")) return {{0.30, 0.42, 0.22}, {0.18, 0.28, 0.14}, {0.20, 0.22, 0.25}};
  if (has("stomach") || has("bowel") || has("intestine") || has("duoden") || has("colon"))
    return {{0.72, 0.42, 0.38}, {0.55, 0.28, 0.26}, {0.45, 0.20, 0.28}};
  return {{0.66, 0.32, 0.27}, {0.46, 0.19, 0.16}, {0.38, 0.14, 0.22}};
}

}  // namespace

void box_chart_uvs(TriMesh& mesh) {
  const Aabb box = mesh.bounds();
  const Real scale = 1.0 / extent(mesh);
  mesh.texcoords.assign(3 * mesh.triangle_count(), Vec2::Zero());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const int chart = chart_of(mesh.triangle_normal_area2(t));
    const auto [ua, va] = chart_axes(chart);
    const bool negative = chart % 2 == 1;
    const Real col = chart % 3, row = chart / 3;
    for (int c = 0; c < 3; ++c) {
      const Vec3 p = mesh.positions[mesh.triangles[t][static_cast<std::size_t>(c)]];
      Real u = (p[ua] - box.min[ua]) * scale;
      const Real v = (p[va] - box.min[va]) * scale;
      if (negative) u = (box.max[ua] - box.min[ua]) * scale - u;  // seen from −axis: mirror u
      mesh.texcoords[3 * t + static_cast<std::size_t>(c)] =
          Vec2((col + kGutter + (1 - 2 * kGutter) * u) / 3.0, (row + kGutter + (1 - 2 * kGutter) * v) / 2.0);
    }
  }
}

Real atlas_texel_size(const TriMesh& mesh, std::size_t chart_pixels) {
  return extent(mesh) / ((1 - 2 * kGutter) * static_cast<Real>(chart_pixels));
}

RgbImage organ_texture(const std::string& organ, std::size_t chart_pixels, Real texel_m) {
  RgbImage image;
  image.width = 3 * chart_pixels;
  image.height = 2 * chart_pixels;
  image.rgb.resize(3 * image.width * image.height);
  const Palette pal = palette_for(organ);
  const Real mm = texel_m * 1e3;  // millimetres per texel
  for (std::size_t y = 0; y < image.height; ++y) {
    for (std::size_t x = 0; x < image.width; ++x) {
      const Real px = static_cast<Real>(x) * mm, py = static_cast<Real>(y) * mm;
      const Real mottling = fbm(px / 6.0, py / 6.0, 5, 7u);   // ~6 mm blotches
      const Real lobules = fbm(px / 1.5, py / 1.5, 3, 19u);   // ~1.5 mm grain
      // Ridged noise: thin lines where a smooth field crosses 0.5 (vessels under the capsule).
      const Real ridge = 1 - std::abs(2 * fbm(px / 14.0, py / 14.0, 4, 43u) - 1);
      const Real vessel = std::pow(std::clamp((ridge - 0.93) / 0.07, 0.0, 1.0), 2.0);
      Vec3 colour = pal.dark + (pal.base - pal.dark) * std::clamp(0.5 + 1.6 * (mottling - 0.5), 0.0, 1.0);
      colour *= 0.9 + 0.2 * lobules;
      colour = colour + (pal.vessel - colour) * (0.7 * vessel);
      // PNG rows run top to bottom, v runs bottom to top: row y holds v = 1 − (y + ½)/height.
      const std::size_t row = image.height - 1 - y;
      for (int c = 0; c < 3; ++c) {
        image.rgb[3 * (row * image.width + x) + static_cast<std::size_t>(c)] =
            static_cast<std::uint8_t>(std::clamp(colour[c] * 255.0 + 0.5, 0.0, 255.0));
      }
    }
  }
  return image;
}

void write_png(const RgbImage& image, const std::filesystem::path& path) {
  if (image.width == 0 || image.height == 0 || image.rgb.size() != 3 * image.width * image.height) {
    throw FileError(path.string(), FileLocation::none(), "write_png: the image is empty or of the wrong size");
  }
  vtkNew<vtkImageData> data;
  data->SetDimensions(static_cast<int>(image.width), static_cast<int>(image.height), 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* out = static_cast<std::uint8_t*>(data->GetScalarPointer());
  // vtkImageData rows run bottom to top; RgbImage rows top to bottom.
  for (std::size_t y = 0; y < image.height; ++y) {
    std::memcpy(out + 3 * image.width * (image.height - 1 - y), image.rgb.data() + 3 * image.width * y, 3 * image.width);
  }
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(path.string().c_str());
  writer->SetInputData(data);
  writer->Write();
  if (writer->GetErrorCode() != 0) throw FileError(path.string(), FileLocation::none(), "cannot write the PNG");
}

}  // namespace trocar

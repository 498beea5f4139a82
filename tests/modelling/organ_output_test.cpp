// What a build writes: OBJ + MTL + PNG and VRML97 read back to the same organ with its UVs;
// the box-chart UVs are inside the atlas and never flip a triangle; the report carries the
// figures docs/modelling.md "The report" lists.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "trocar/mesh/io/mesh_io.h"
#include "trocar/modelling/organ_builder.h"
#include "trocar/modelling/organ_writers.h"
#include "trocar/modelling/phantoms.h"

namespace trocar {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() {
  const fs::path dir = fs::temp_directory_path() / ("trocar_organ_out_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Width and height from a PNG's IHDR (big-endian at bytes 16 and 20).
std::pair<unsigned, unsigned> png_size(const fs::path& p) {
  const std::string b = read_text(p);
  if (b.size() < 24 || b.compare(1, 3, "PNG") != 0) return {0, 0};
  const auto be = [&](std::size_t at) {
    return (static_cast<unsigned>(static_cast<unsigned char>(b[at])) << 24) | (static_cast<unsigned>(static_cast<unsigned char>(b[at + 1])) << 16) |
           (static_cast<unsigned>(static_cast<unsigned char>(b[at + 2])) << 8) | static_cast<unsigned>(static_cast<unsigned char>(b[at + 3]));
  };
  return {be(16), be(20)};
}

const OrganBuild& torus_build() {
  static const OrganBuild b = [] {
    OrganBuildOptions o;
    o.query.label = "1";
    o.surface.target_triangles = 3000;
    o.texture_chart_pixels = 64;
    return build_organ(torus_phantom(1e-3).volume, o);
  }();
  return b;
}

TEST(BoxChartUvs, InsideTheAtlasAndNeverFlipped) {
  const TriMesh& m = torus_build().mesh;
  ASSERT_EQ(m.texcoords.size(), 3 * m.triangle_count());
  std::array<std::size_t, 6> per_chart{};
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec2 a = m.texcoords[3 * t], b = m.texcoords[3 * t + 1], c = m.texcoords[3 * t + 2];
    for (const Vec2& uv : {a, b, c}) {
      EXPECT_GE(uv.minCoeff(), 0.0);
      EXPECT_LE(uv.maxCoeff(), 1.0);
    }
    const Vec2 e1 = b - a, e2 = c - a;
    EXPECT_GT(e1.x() * e2.y() - e1.y() * e2.x(), 0.0) << "triangle " << t;  // counter-clockwise in UV, as on the organ
    // All three corners in one chart cell of the 3 × 2 atlas.
    const int col = static_cast<int>(a.x() * 3), row = static_cast<int>(a.y() * 2);
    for (const Vec2& uv : {b, c}) {
      EXPECT_EQ(static_cast<int>(uv.x() * 3), col);
      EXPECT_EQ(static_cast<int>(uv.y() * 2), row);
    }
    ++per_chart[static_cast<std::size_t>(row * 3 + col)];
  }
  for (std::size_t n : per_chart) EXPECT_GT(n, 0u);  // a torus faces all six ways
}

TEST(BoxChartUvs, StretchIsBoundedByRootThree) {
  // Orthographic projection onto the dominant axis plane: a triangle's UV area is at least
  // 1/√3 of its (scaled) 3-D area.
  const TriMesh& m = torus_build().mesh;
  const Real scale = (1 - 2 * 0.03) / m.bounds().size().maxCoeff();
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec2 e1 = m.texcoords[3 * t + 1] - m.texcoords[3 * t], e2 = m.texcoords[3 * t + 2] - m.texcoords[3 * t];
    const Real uv_area = 0.5 * (e1.x() * e2.y() - e1.y() * e2.x()) * 6;  // a chart cell is 1/3 × 1/2
    const Real area = 0.5 * m.triangle_normal_area2(t).norm() * scale * scale;
    EXPECT_GE(uv_area, area / std::sqrt(3.0) * (1 - 1e-9));
    EXPECT_LE(uv_area, area * (1 + 1e-9));
  }
}

TEST(OrganOutput, ObjMtlPngReadBack) {
  const OrganBuild& b = torus_build();
  const fs::path obj = temp_dir() / "torus.obj";
  write_organ(b, obj);
  const TriMesh back = load_mesh(obj);
  EXPECT_EQ(back.triangles, b.mesh.triangles);
  ASSERT_EQ(back.texcoords.size(), b.mesh.texcoords.size());
  for (std::size_t i = 0; i < back.positions.size(); ++i) EXPECT_EQ(back.positions[i], b.mesh.positions[i]);
  for (std::size_t i = 0; i < back.texcoords.size(); ++i) EXPECT_EQ(back.texcoords[i], b.mesh.texcoords[i]);
  const std::string text = read_text(obj);
  EXPECT_NE(text.find("mtllib torus.mtl\nusemtl organ\n"), std::string::npos);
  EXPECT_LT(text.find("usemtl organ"), text.find("\nf "));
  const std::string mtl = read_text(temp_dir() / "torus.mtl");
  EXPECT_NE(mtl.find("map_Kd torus.png"), std::string::npos);
  EXPECT_NE(mtl.find("newmtl organ"), std::string::npos);
  EXPECT_EQ(png_size(temp_dir() / "torus.png"), (std::pair<unsigned, unsigned>{192, 128}));
}

TEST(OrganOutput, VrmlReadBackWithItsTexture) {
  const OrganBuild& b = torus_build();
  const fs::path wrl = temp_dir() / "torus.wrl";
  write_organ(b, wrl);
  const std::string text = read_text(wrl);
  EXPECT_EQ(text.rfind("#VRML V2.0 utf8", 0), 0u);
  EXPECT_NE(text.find("ImageTexture { url \"torus.png\" }"), std::string::npos);
  EXPECT_NE(text.find("texCoordIndex"), std::string::npos);
  const TriMesh back = load_mesh(wrl);
  EXPECT_EQ(back.triangle_count(), b.mesh.triangle_count());
  EXPECT_NEAR(back.signed_volume(), b.mesh.signed_volume(), 1e-12);
  EXPECT_TRUE(fs::is_regular_file(temp_dir() / "torus.png"));
}

TEST(OrganOutput, UnknownExtensionIsAnErrorAndWritesNothing) {
  const fs::path out = temp_dir() / "torus.fbx";
  EXPECT_THROW(write_organ(torus_build(), out), FileError);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(temp_dir() / "torus_never.png"));
}

TEST(OrganOutput, TextureIsDeterministicAndOrganColoured) {
  const RgbImage liver = organ_texture("liver", 32, 1e-3);
  EXPECT_EQ(liver.rgb, organ_texture("liver", 32, 1e-3).rgb);
  const Vec3 liver_mean = organ_colour("liver"), gall = organ_colour("gallbladder");
  EXPECT_GT(liver_mean.x(), liver_mean.y());  // red-brown
  EXPECT_GT(gall.y(), gall.x());              // green
  // Not flat: the mottling spreads the red channel.
  int lo = 255, hi = 0;
  for (std::size_t p = 0; p < liver.width * liver.height; ++p) {
    lo = std::min<int>(lo, liver.rgb[3 * p]);
    hi = std::max<int>(hi, liver.rgb[3 * p]);
  }
  EXPECT_GT(hi - lo, 30);
}

TEST(BuildReport, CarriesTheIssueFigures) {
  const Phantom p = torus_phantom(1e-3);
  const nlohmann::json r = build_report(torus_build(), p.volume);
  EXPECT_EQ(r.at("triangles").get<std::size_t>(), torus_build().mesh.triangle_count());
  EXPECT_EQ(r.at("genus").get<int>(), 1);
  EXPECT_TRUE(r.at("closed").get<bool>());
  EXPECT_TRUE(r.at("manifold").get<bool>());
  EXPECT_LT(std::abs(r.at("volume_error_percent").get<double>()), 1.0);
  EXPECT_LT(r.at("hausdorff").at("max_voxels").get<double>(), 1.0);
  EXPECT_NEAR(r.at("hausdorff").at("max_mm").get<double>(), r.at("hausdorff").at("max_voxels").get<double>(), 1e-9);
  std::size_t binned = 0;
  for (const auto& bin : r.at("aspect_ratio_histogram")) binned += bin.at("triangles").get<std::size_t>();
  EXPECT_EQ(binned, torus_build().mesh.triangle_count());
  EXPECT_GT(r.at("min_angle_deg").get<double>(), 0.0);
  for (const char* stage : {"components", "extract", "smooth", "decimate", "clean", "checks", "uv", "texture", "total"})
    EXPECT_GE(r.at("seconds").at(stage).get<double>(), 0.0) << stage;
}

}  // namespace
}  // namespace trocar

// write_obj / write_stl_binary, and read → write → read round trips (synthetic and shared files).
#include <gtest/gtest.h>

#include <bit>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "support/shared_data.h"
#include "test_util.h"
#include "trocar/mesh/io/mesh_io.h"

namespace trocar {
namespace {

template <int N>
bool bit_identical(const std::vector<Eigen::Matrix<Real, N, 1>>& a, const std::vector<Eigen::Matrix<Real, N, 1>>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < N; ++k)
      if (std::bit_cast<std::uint64_t>(a[i][k]) != std::bit_cast<std::uint64_t>(b[i][k])) return false;
  return true;
}

TriMesh tricky_mesh() {
  TriMesh m;
  m.positions = {Vec3(0.1, 1.0 / 3.0, -0.0),
                 Vec3(std::numeric_limits<double>::denorm_min(), 1e-310, std::numeric_limits<double>::max()),
                 Vec3(-123456789.123456789, 2.0 / 3.0, 1030.3612345678901),
                 Vec3(std::nextafter(1.0, 2.0), -std::numeric_limits<double>::min(), 5e-324),
                 Vec3(7, 8, 9)};  // unused
  m.triangles = {{0, 1, 2}, {2, 1, 3}, {3, 3, 0}};
  return m;
}

TEST(ObjWriter, RoundTripIsBitIdentical) {
  TriMesh m = tricky_mesh();
  const TriMesh back = read_obj(write_obj(m), "w.obj");
  EXPECT_TRUE(bit_identical(m.positions, back.positions));
  EXPECT_EQ(m.triangles, back.triangles);
  EXPECT_TRUE(back.normals.empty());
  EXPECT_TRUE(back.texcoords.empty());

  m.normals = {Vec3(0, 0, 1), Vec3(0.6, 0.8, 0), Vec3(1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0), Vec3(-1, 0, 0), Vec3(0, 1, 0)};
  m.texcoords.clear();
  for (int i = 0; i < 9; ++i) m.texcoords.push_back(Vec2(i / 7.0, 1.0 - i / 9.0));
  const std::string text = write_obj(m);
  const TriMesh back2 = read_obj(text, "w.obj");
  EXPECT_TRUE(bit_identical(m.positions, back2.positions));
  EXPECT_EQ(m.triangles, back2.triangles);
  // Vertex 4 is unused: its normal is written but no corner refers to it, so it reads back as 0.
  m.normals[4] = Vec3::Zero();
  EXPECT_TRUE(bit_identical(m.normals, back2.normals));
  EXPECT_TRUE(bit_identical(m.texcoords, back2.texcoords));
  EXPECT_NE(text.find("\nf 1/1/1 2/2/2 3/3/3\n"), std::string::npos) << text;
}

TEST(ObjWriter, FormsWithOnlyNormalsOrOnlyTexcoords) {
  TriMesh m = tricky_mesh();
  m.normals.assign(5, Vec3(0, 0, 1));
  EXPECT_NE(write_obj(m).find("\nf 1//1 2//2 3//3\n"), std::string::npos);
  m.normals.clear();
  m.texcoords.assign(9, Vec2(0.5, 0.5));
  EXPECT_NE(write_obj(m).find("\nf 3/4 2/5 4/6\n"), std::string::npos);
}

TEST(StlWriter, LayoutAndRoundTrip) {
  TriMesh m = tricky_mesh();
  m.positions[1] = Vec3(1, 0, 0);  // keep every coordinate inside float range
  m.positions[3] = Vec3(0.25, 1e-3, 4);
  const std::string bytes = write_stl_binary(m);
  ASSERT_EQ(bytes.size(), 84u + 50u * 3u);
  EXPECT_EQ(bytes.substr(0, 6), "trocar");
  EXPECT_NE(bytes.substr(0, 5), "solid");
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  EXPECT_EQ(count, 3u);
  float normal[3];
  std::memcpy(normal, bytes.data() + 84, 12);
  EXPECT_NEAR(std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]), 1.0, 1e-6);
  float degenerate_normal[3];
  std::memcpy(degenerate_normal, bytes.data() + 84 + 100, 12);  // triangle {3,3,0}
  EXPECT_EQ(degenerate_normal[0], 0.0f);
  for (int t = 0; t < 3; ++t) EXPECT_EQ(bytes.substr(84 + 50 * t + 48, 2), std::string(2, '\0'));

  const TriMesh back = read_stl(bytes, "w.stl");
  ASSERT_EQ(back.triangle_count(), 3u);
  EXPECT_EQ(back.vertex_count(), 4u);  // the unused vertex is gone
  for (std::size_t t = 0; t < 3; ++t)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(back.corners(t)[c][k], double(static_cast<float>(m.corners(t)[c][k])));
}

TEST(Writers, RejectInvalidMeshes) {
  TriMesh m = tricky_mesh();
  m.triangles.push_back({0, 1, 5});
  EXPECT_THROW((void)write_obj(m), Error);
  EXPECT_THROW((void)write_stl_binary(m), Error);
  m = tricky_mesh();
  m.positions[0].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)write_obj(m), Error);
  EXPECT_THROW((void)write_stl_binary(m), Error);
  m = tricky_mesh();  // max double does not fit in float32
  EXPECT_THROW((void)write_stl_binary(m), Error);
}

TEST(Writers, SaveAndLoadFiles) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("trocar_mesh_io_" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
  std::filesystem::create_directories(dir);
  TriMesh m = tricky_mesh();
  m.positions[1] = Vec3(1, 0, 0);
  save_mesh(m, dir / "a.obj");
  save_mesh(m, dir / "a.STL");
  const TriMesh obj = load_mesh(dir / "a.obj");
  EXPECT_TRUE(bit_identical(m.positions, obj.positions));
  const TriMesh stl = load_mesh(dir / "a.STL");
  EXPECT_EQ(stl.triangle_count(), 3u);
  // A binary STL renamed .obj is reported by the OBJ reader with the path.
  std::filesystem::copy_file(dir / "a.STL", dir / "b.obj");
  EXPECT_TRUE(test::throws_file_error([&] { (void)load_mesh(dir / "b.obj"); }, (dir / "b.obj").string(),
                                      FileLocation::line(1), "not a text OBJ file"));
  std::filesystem::remove_all(dir);
}

// ---- the shared meshes through both writers ----

std::string test_name(const ::testing::TestParamInfo<const char*>& param_info) {
  std::string n = param_info.param;
  for (char& c : n)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return n;
}

class SharedRoundTrip : public ::testing::TestWithParam<const char*> {};

TEST_P(SharedRoundTrip, ThroughObjAndStl) {
  TROCAR_SHARED_MESH_OR_SKIP(path, GetParam());  // absent in a user's clone, or hidden (TROCAR_HIDE_SHARED)
  const TriMesh m = load_mesh(path);

  const TriMesh via_obj = read_obj(write_obj(m), "rt.obj");
  EXPECT_TRUE(bit_identical(m.positions, via_obj.positions));
  EXPECT_EQ(m.triangles, via_obj.triangles);
  EXPECT_EQ(m.normals.size(), via_obj.normals.size());

  const TriMesh via_stl = read_stl(write_stl_binary(m), "rt.stl");
  ASSERT_EQ(via_stl.triangle_count(), m.triangle_count());
  for (std::size_t t = 0; t < m.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(via_stl.corners(t)[c][k], double(static_cast<float>(m.corners(t)[c][k]))) << "triangle " << t;
  if (path.extension() == ".stl") {
    // Positions came from float32 and were welded already: the very same mesh comes back.
    EXPECT_TRUE(bit_identical(m.positions, via_stl.positions));
    EXPECT_EQ(m.triangles, via_stl.triangles);
  } else {
    // Welding a second time changes nothing.
    const TriMesh again = read_stl(write_stl_binary(via_stl), "rt2.stl");
    EXPECT_EQ(again.vertex_count(), via_stl.vertex_count());
    EXPECT_EQ(again.triangles, via_stl.triangles);
  }
}

INSTANTIATE_TEST_SUITE_P(MeshIo, SharedRoundTrip,
                         ::testing::Values("liver_sofa_smooth.obj", "liver_sofa_coarse.obj",
                                           "liver_bodyparts3d_FMA7197.obj", "kidney_right_bodyparts3d_FMA7204.obj",
                                           "stomach_bodyparts3d_FMA7148.obj", "gallbladder_lapgym.stl",
                                           "duodenum_openhelp.stl", "abdominal_wall_openhelp.stl",
                                           "grasper_jaw_maryland_left_lapgym.stl", "probe_hook_electrode_lapgym.stl",
                                           "laparoscope_optics_lapgym.stl"),
                         test_name);

}  // namespace
}  // namespace trocar

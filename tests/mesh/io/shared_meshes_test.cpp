// Every OBJ and STL file of the shared test meshes loads with the counts and bounding boxes of
// ../shared/data/meshes/SOURCES.md; where assimp is linked it serves as an independent oracle.
// Skipped when the folder is absent (a clone without ../shared).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.h"
#include "trocar/mesh/io/mesh_io.h"

#ifdef TROCAR_HAVE_ASSIMP
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#endif

namespace trocar {
namespace {

struct Expected {
  const char* file;
  std::size_t vertices;
  std::size_t triangles;
  std::array<double, 3> min;
  std::array<double, 3> max;
  std::size_t boundary_edges;
  std::size_t unused_vertices;
};

// From SOURCES.md (OBJ counts are before any welding; STL counts after welding equal corners).
const Expected kExpected[] = {
    {"liver_sofa_smooth.obj", 2194, 4384, {-4.658, 0.264, -1.674}, {1.728, 5.172, 2.738}, 0, 0},
    {"liver_sofa_coarse.obj", 181, 274, {-4.679, 0.218, -1.693}, {1.803, 5.157, 2.729}, 0, 42},
    {"liver_bodyparts3d_FMA7197.obj", 1965, 3882, {-117.97, -192.32, 1030.36}, {81.03, -42.44, 1204.31}, 70, 0},
    {"kidney_right_bodyparts3d_FMA7204.obj", 1253, 2478, {-95.46, -97.82, 999.60}, {-35.44, -44.83, 1101.82}, 34, 0},
    {"stomach_bodyparts3d_FMA7148.obj", 4694, 9384, {-27.54, -195.54, 1061.67}, {114.21, -80.31, 1181.87}, 0, 0},
    {"gallbladder_lapgym.stl", 7352, 14700, {-83.74, -27.35, -47.98}, {6.31, 29.81, 2.70}, 0, 0},
    {"duodenum_openhelp.stl", 3475, 6946, {-44.77, -3.87, 111.80}, {55.96, 129.10, 178.16}, 0, 0},
    {"abdominal_wall_openhelp.stl", 15969, 31934, {-126.42, -248.59, 139.86}, {151.51, 197.02, 294.65}, 0, 0},
    {"grasper_jaw_maryland_left_lapgym.stl", 478, 952, {-2.257, -6.181, -2.385}, {2.257, 2.352, 25.696}, 0, 0},
    {"probe_hook_electrode_lapgym.stl", 836, 1664, {-2.228, -2.168, -349.31}, {2.228, 2.270, 15.167}, 0, 0},
    {"laparoscope_optics_lapgym.stl", 717, 1388, {-15.94, -40.80, -380.5}, {15.94, 15.94, 0.026}, 36, 0},
};

// Test names and failure messages show the file, not the struct's bytes.
void PrintTo(const Expected& e, std::ostream* os) { *os << e.file; }

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Edges used by exactly one triangle.
std::size_t boundary_edges(const TriMesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const Triangle& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k];
      const std::uint32_t b = t[(k + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  return static_cast<std::size_t>(std::count_if(uses.begin(), uses.end(), [](const auto& e) { return e.second == 1; }));
}

std::size_t unused_vertices(const TriMesh& m) {
  std::vector<bool> used(m.vertex_count(), false);
  for (const Triangle& t : m.triangles)
    for (std::uint32_t v : t) used[v] = true;
  return static_cast<std::size_t>(std::count(used.begin(), used.end(), false));
}

std::string test_name(const ::testing::TestParamInfo<Expected>& param_info) {
  std::string n = param_info.param.file;
  for (char& c : n)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return n;
}

class SharedMeshes : public ::testing::TestWithParam<Expected> {
 protected:
  void SetUp() override {
    if (!test::shared_meshes_dir()) GTEST_SKIP() << test::shared_absent(GetParam().file);
  }
};

TEST_P(SharedMeshes, CountsAndBounds) {
  const Expected& e = GetParam();
  const std::filesystem::path path = test::shared_mesh(e.file);
  const TriMesh m = load_mesh(path);
  EXPECT_EQ(m.vertex_count(), e.vertices);
  EXPECT_EQ(m.triangle_count(), e.triangles);
  EXPECT_TRUE(m.indices_valid());
  const Aabb box = m.bounds();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(box.min[k], e.min[k], 1e-2) << "axis " << k;
    EXPECT_NEAR(box.max[k], e.max[k], 1e-2) << "axis " << k;
  }
  EXPECT_EQ(boundary_edges(m), e.boundary_edges);
  EXPECT_EQ(unused_vertices(m), e.unused_vertices);
  EXPECT_GT(m.signed_volume(), 0.0);  // every file is oriented outward
}

TEST_P(SharedMeshes, Attributes) {
  const Expected& e = GetParam();
  const TriMesh m = load_mesh(test::shared_mesh(e.file));
  const std::string name = e.file;
  EXPECT_TRUE(m.texcoords.empty());
  const bool has_vn = name.find("coarse") == std::string::npos && name.ends_with(".obj");
  if (!has_vn) {
    EXPECT_TRUE(m.normals.empty());
    return;
  }
  ASSERT_EQ(m.normals.size(), m.vertex_count());
  for (const Vec3& n : m.normals) EXPECT_NEAR(n.norm(), 1.0, 1e-4);
  // The normals agree with the surface: on average they point along the face normals.
  double agreement = 0;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 fn = m.triangle_normal_area2(t).normalized();
    for (std::uint32_t v : m.triangles[t]) agreement += fn.dot(m.normals[v]);
  }
  EXPECT_GT(agreement / (3.0 * static_cast<double>(m.triangle_count())), 0.8);
}

// (How long a load takes is bench_mesh's to measure: bench/mesh/load_bench.cpp.)
TEST_P(SharedMeshes, TheSameBytesReadToTheSameMesh) {
  const Expected& e = GetParam();
  const std::filesystem::path path = test::shared_mesh(e.file);
  const std::string bytes = read_bytes(path);
  const MeshFormat format = format_from_path(path);
  const TriMesh first = read_mesh(bytes, format, e.file), second = read_mesh(bytes, format, e.file);
  ASSERT_EQ(first.triangle_count(), e.triangles);
  EXPECT_EQ(first.triangles, second.triangles);
  ASSERT_EQ(first.positions.size(), second.positions.size());
  for (std::size_t i = 0; i < first.positions.size(); ++i)
    ASSERT_EQ(first.positions[i], second.positions[i]) << "vertex " << i;
}

#ifdef TROCAR_HAVE_ASSIMP
// assimp splits vertices per corner, so compare corner positions triangle by triangle (assimp
// keeps the face order for these single-object files), and the number of distinct positions.
TEST_P(SharedMeshes, AgreesWithAssimp) {
  const Expected& e = GetParam();
  const std::string path = test::shared_mesh(e.file);
  const TriMesh m = load_mesh(path);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  std::vector<std::array<std::array<float, 3>, 3>> theirs;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
    const aiMesh* mesh = scene->mMeshes[i];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      std::array<std::array<float, 3>, 3> tri{};
      for (int c = 0; c < 3; ++c) {
        const aiVector3D& p = mesh->mVertices[face.mIndices[c]];
        tri[c] = {p.x, p.y, p.z};
      }
      theirs.push_back(tri);
    }
  }
  ASSERT_EQ(theirs.size(), m.triangle_count());
  // OBJ: assimp's own float parsing may differ from correct rounding by an ulp or so.
  const bool binary = path.ends_with(".stl");
  std::set<std::array<float, 3>> ours_distinct;
  std::set<std::array<float, 3>> theirs_distinct;
  std::size_t mismatches = 0;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    for (int c = 0; c < 3; ++c) {
      const Vec3& p = m.positions[m.triangles[t][c]];
      std::array<float, 3> q{};
      for (int k = 0; k < 3; ++k) {
        q[k] = static_cast<float>(p[k]);
        const double tol = binary ? 0.0 : 1e-6 * (1.0 + std::abs(p[k]));
        if (std::abs(double(theirs[t][c][k]) - p[k]) > tol && mismatches++ < 5) {
          ADD_FAILURE() << "triangle " << t << " corner " << c << " axis " << k << ": " << p[k] << " vs assimp "
                        << theirs[t][c][k];
        }
      }
      ours_distinct.insert(q);
      theirs_distinct.insert(theirs[t][c]);
    }
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(ours_distinct.size(), theirs_distinct.size());
}
#endif

INSTANTIATE_TEST_SUITE_P(MeshIo, SharedMeshes, ::testing::ValuesIn(kExpected), test_name);

TEST(SharedMeshesWelding, BodyParts3DDuplicatesMergeToSourcesCounts) {
  // SOURCES.md: merging by position gives 1943 V (liver) and 1241 V (kidney).
  if (!test::shared_meshes_dir()) GTEST_SKIP() << test::shared_absent("liver_bodyparts3d_FMA7197.obj");
  for (const auto& [file, merged] : {std::pair{"liver_bodyparts3d_FMA7197.obj", 1943u},
                                     std::pair{"kidney_right_bodyparts3d_FMA7204.obj", 1241u}}) {
    const TriMesh m = load_mesh(test::shared_mesh(file));
    std::set<std::array<double, 3>> distinct;
    for (const Vec3& p : m.positions) distinct.insert({p.x(), p.y(), p.z()});
    EXPECT_EQ(distinct.size(), merged) << file;
  }
}

}  // namespace
}  // namespace trocar

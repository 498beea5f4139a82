// validate() and repair() on the third-party meshes of ../shared/data/meshes, against the
// numbers in SOURCES.md. Skipped when the folder is absent (or a reader is not there yet).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>
#include <string>

#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/repair.h"
#include "trocar/mesh/topology.h"
#include "trocar/mesh/validate.h"
#include "support/shared_data.h"

namespace trocar {
namespace {

struct Expected {
  const char* file;
  std::size_t vertices;
  std::size_t triangles;
  std::size_t boundary_edges;
  std::size_t components;
  std::size_t unused_vertices;
  std::size_t duplicate_vertices;
};

// SOURCES.md's summary table. Every file: 0 non-manifold edges, 0 degenerate and 0
// duplicate triangles, positive signed volume.
const Expected kFiles[] = {
    {"liver_sofa_smooth.obj", 2194, 4384, 0, 1, 0, 0},
    {"liver_sofa_smooth.wrl", 2194, 4384, 0, 1, 0, 0},
    {"liver_sofa_coarse.obj", 181, 274, 0, 1, 42, 0},
    {"liver_bodyparts3d_FMA7197.obj", 1965, 3882, 70, 1, 0, 22},
    {"gallbladder_lapgym.stl", 7352, 14700, 0, 1, 0, 0},
    {"kidney_right_bodyparts3d_FMA7204.obj", 1253, 2478, 34, 1, 0, 12},
    {"stomach_bodyparts3d_FMA7148.obj", 4694, 9384, 0, 1, 0, 0},
    {"duodenum_openhelp.stl", 3475, 6946, 0, 1, 0, 0},
    {"abdominal_wall_openhelp.stl", 15969, 31934, 0, 1, 0, 0},
    {"grasper_jaw_maryland_left_lapgym.stl", 478, 952, 0, 1, 0, 0},
    {"probe_hook_electrode_lapgym.stl", 836, 1664, 0, 2, 0, 0},
    {"laparoscope_optics_lapgym.stl", 717, 1388, 36, 3, 0, 0},
};

/// Loads a shared mesh, or explains why the test must be skipped (empty optional).
std::optional<TriMesh> load_shared(const std::string& file, std::string& why) {
  const std::optional<std::filesystem::path> path = test::shared_mesh_path(file);
  if (!path) {
    why = test::shared_absent(file);
    return std::nullopt;
  }
  try {
    return load_mesh(*path);
  } catch (const Error& e) {
    const std::string what = e.what();
    if (what.find("not implemented") != std::string::npos) {  // reader still a placeholder
      why = what;
      return std::nullopt;
    }
    throw;
  }
}

class SharedMesh : public ::testing::TestWithParam<Expected> {};

TEST_P(SharedMesh, ValidateMatchesSources) {
  const Expected& x = GetParam();
  std::string why;
  const auto mesh = load_shared(x.file, why);
  if (!mesh) GTEST_SKIP() << why;
  const MeshReport r = validate(*mesh);
  EXPECT_EQ(r.vertices, x.vertices);
  EXPECT_EQ(r.triangles, x.triangles);
  EXPECT_EQ(r.boundary_edges, x.boundary_edges);
  EXPECT_EQ(r.nonmanifold_edges, 0u);
  EXPECT_EQ(r.components, x.components);
  EXPECT_EQ(r.unused_vertices, x.unused_vertices);
  EXPECT_EQ(r.duplicate_vertices, x.duplicate_vertices);
  EXPECT_EQ(r.degenerate_triangles, 0u);
  EXPECT_EQ(r.duplicate_triangles, 0u);
  EXPECT_EQ(r.out_of_range_triangles, 0u);
  EXPECT_EQ(r.nonfinite_vertices, 0u);
  EXPECT_GT(r.signed_volume, 0);
  EXPECT_EQ(r.closed, x.boundary_edges == 0);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  if (r.closed) {
    EXPECT_EQ(r.orientation, Orientation::kOutward);
    EXPECT_EQ(r.euler_characteristic % 2, 0);
  }
}

TEST_P(SharedMesh, RepairKeepsCleanFilesAndClosesCracks) {
  const Expected& x = GetParam();
  std::string why;
  auto mesh = load_shared(x.file, why);
  if (!mesh) GTEST_SKIP() << why;
  const RepairReport rep = repair(*mesh);
  EXPECT_EQ(rep.vertices_merged, x.duplicate_vertices);
  EXPECT_EQ(rep.unused_vertices_removed, x.unused_vertices + x.duplicate_vertices);
  EXPECT_EQ(rep.triangles_after, x.triangles);
  EXPECT_EQ(rep.triangles_flipped, 0u);
  const MeshReport r = validate(*mesh);
  EXPECT_EQ(r.vertices, x.vertices - x.unused_vertices - x.duplicate_vertices);
  EXPECT_EQ(r.components, x.components);
  EXPECT_GT(r.signed_volume, 0);
  if (x.boundary_edges == 0 || x.duplicate_vertices != 0) {
    EXPECT_TRUE(r.closed);
    EXPECT_EQ(r.boundary_edges, 0u);
    EXPECT_EQ(r.nonmanifold_edges, 0u);
    EXPECT_EQ(r.orientation, Orientation::kOutward);
    EXPECT_TRUE(r.is_clean()) << ::testing::PrintToString(r.defects());
  } else {
    EXPECT_TRUE(r.is_clean_open()) << ::testing::PrintToString(r.defects());
    EXPECT_EQ(r.boundary_edges, x.boundary_edges);  // the laparoscope stays open
  }
}

INSTANTIATE_TEST_SUITE_P(Files, SharedMesh, ::testing::ValuesIn(kFiles),
                         [](const ::testing::TestParamInfo<Expected>& param) {
                           std::string name = param.param.file;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

TEST(SharedMesh, BodyParts3dCracksCloseWithRelativeMerge) {
  for (const auto& [file, merged] : {std::pair<const char*, std::size_t>{"liver_bodyparts3d_FMA7197.obj", 1943},
                                     {"kidney_right_bodyparts3d_FMA7204.obj", 1241}}) {
    std::string why;
    auto mesh = load_shared(file, why);
    if (!mesh) GTEST_SKIP() << why;
    RepairOptions opts;
    opts.merge_tolerance_rel = 1e-9;
    repair(*mesh, opts);
    const MeshReport r = validate(*mesh);
    EXPECT_EQ(r.vertices, merged) << file;
    EXPECT_EQ(r.boundary_edges, 0u) << file;
    EXPECT_EQ(r.nonmanifold_edges, 0u) << file;
    EXPECT_TRUE(r.closed) << file;
    EXPECT_EQ(r.orientation, Orientation::kOutward) << file;
    EXPECT_EQ(r.euler_characteristic, 2) << file;
  }
}

TEST(SharedMesh, ProbeComponentsAre1040And624Triangles) {
  std::string why;
  const auto mesh = load_shared("probe_hook_electrode_lapgym.stl", why);
  if (!mesh) GTEST_SKIP() << why;
  const MeshTopology topo(*mesh);
  ASSERT_EQ(topo.component_count(), 2u);
  const auto counts = topo.component_triangle_counts();
  EXPECT_EQ(std::min(counts[0], counts[1]), 624u);
  EXPECT_EQ(std::max(counts[0], counts[1]), 1040u);
}

TEST(SharedMesh, LaparoscopeLightPostIsTheOpenPart) {
  std::string why;
  const auto mesh = load_shared("laparoscope_optics_lapgym.stl", why);
  if (!mesh) GTEST_SKIP() << why;
  const MeshTopology topo(*mesh);
  ASSERT_EQ(topo.component_count(), 3u);
  // All 36 boundary edges lie in the 756-triangle component.
  for (std::uint32_t e : topo.boundary_edges()) {
    const std::uint32_t c = topo.triangle_component(topo.edge_triangles(e)[0]);
    EXPECT_EQ(topo.component_triangle_counts()[c], 756u);
  }
}

}  // namespace
}  // namespace trocar

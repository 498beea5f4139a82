// Scenes that name a volume: the shipped built_liver.json builds its liver from the volume the
// project generates (checked against a fresh generation), caches it by content hash, and runs
// 2 s stably; bad keys and files are errors naming the key; without the builder a clear error.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "trocar/core/error.h"
#include "trocar/mesh/validate.h"
#include "trocar/modelling/build_cache.h"
#include "trocar/modelling/phantoms.h"
#include "trocar/scene/mesh_source.h"
#include "trocar/scene/scene.h"
#include "trocar/sim/simulation.h"
#include "trocar/study/scene_driver.h"

namespace trocar {
namespace {

namespace fs = std::filesystem;
const fs::path kScenes = TROCAR_SCENES_DIR;

/// A private cache folder for this test binary, emptied at the start.
class SceneBuild : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const fs::path dir = fs::temp_directory_path() / ("trocar_cache_test_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    ::setenv("TROCAR_CACHE_DIR", dir.c_str(), 1);
    register_scene_mesh_builder();
  }
  static fs::path cache() { return cache_dir() / "organs"; }
  static std::size_t cached_objs() {
    std::size_t n = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(cache(), ec)) n += e.path().extension() == ".obj" ? 1 : 0;
    return n;
  }
};

std::string error_of(const std::string& text, const fs::path& dir) {
  try {
    parse_scene(text, "inline.json", dir);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string liver_scene(const std::string& mesh) {
  return R"({"schema": 1, "tissues": [{"name": "liver", "mesh": )" + mesh + R"(, "material": {"preset": "liver"}}]})";
}

TEST_F(SceneBuild, ShippedVolumeIsWhatThePhantomGeneratorMakes) {
  const Volume shipped = read_volume(kScenes / "volumes" / "abdomen_phantom.nii.gz");
  const Phantom fresh = abdomen_phantom(2e-3);
  EXPECT_EQ(shipped.dims, fresh.volume.dims);
  EXPECT_LT((shipped.spacing - fresh.volume.spacing).norm(), 1e-12);
  EXPECT_LT((shipped.origin - fresh.volume.origin).norm(), 1e-9);
  EXPECT_EQ(shipped.layers.at(0), fresh.volume.layers.at(0));
}

TEST_F(SceneBuild, BuildsOnceThenReadsTheCache) {
  const auto t0 = std::chrono::steady_clock::now();
  const Scene first = load_scene(kScenes / "built_liver.json");
  const double cold = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(first.world.tissues.size(), 1u);
  const auto& liver = first.world.tissues[0]->settings;
  EXPECT_GT(liver.triangles.size(), 5400u);
  EXPECT_LE(liver.triangles.size(), 6000u);
  EXPECT_EQ(cached_objs(), 1u);
  const auto t1 = std::chrono::steady_clock::now();
  const Scene second = load_scene(kScenes / "built_liver.json");
  const double warm = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  EXPECT_EQ(cached_objs(), 1u);
  EXPECT_EQ(second.world.tissues[0]->state.positions, first.world.tissues[0]->state.positions);
  std::printf("built_liver.json: first load %.3f s (build), second %.3f s (cache)\n", cold, warm);
}

TEST_F(SceneBuild, BuiltLiverRunsTwoSecondsStably) {
  Scene scene = load_scene(kScenes / "built_liver.json");
  Simulation sim = make_simulation(scene);
  Real max_speed = 0;
  std::uint64_t applied = 0;
  const DriveResult run = drive(sim, scene.timestep, 2000, [&](const StepMetrics& m) {
    max_speed = std::max(max_speed, m.max_speed);
    applied += m.contacts_applied;
  });
  EXPECT_TRUE(run.stable);        // core/stability.h
  EXPECT_EQ(run.steps, 2000u);
  EXPECT_LT(max_speed, 10.0);     // no vertex flung away (tests/apps/shipped_scenes_test.cpp)
  EXPECT_GT(applied, 0u);  // the probe does press the liver
  TriMesh deformed;
  deformed.positions = sim.world().tissues[0]->state.positions;
  deformed.triangles = sim.world().tissues[0]->settings.triangles;
  const MeshReport r = validate(deformed);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.orientation, Orientation::kOutward);  // pressed, not turned inside out
}

TEST_F(SceneBuild, DamagedCacheEntryIsRebuilt) {
  load_scene(kScenes / "built_liver.json");
  for (const auto& e : fs::directory_iterator(cache())) {
    if (e.path().extension() == ".obj") std::ofstream(e.path(), std::ios::trunc) << "garbage\n";
  }
  const Scene again = load_scene(kScenes / "built_liver.json");
  EXPECT_GT(again.world.tissues[0]->settings.triangles.size(), 5400u);
}

TEST_F(SceneBuild, UnwritableCacheStillBuildsTheScene) {
  const std::string saved = cache_dir().string();
  const fs::path blocker = fs::temp_directory_path() / ("trocar_cache_blocker_" + std::to_string(::getpid()));
  std::ofstream(blocker) << "a file where the cache folder should be\n";
  ::setenv("TROCAR_CACHE_DIR", blocker.c_str(), 1);
  const Scene scene = load_scene(kScenes / "built_liver.json");
  ::setenv("TROCAR_CACHE_DIR", saved.c_str(), 1);
  fs::remove(blocker);
  EXPECT_GT(scene.world.tissues[0]->settings.triangles.size(), 5400u);
}

TEST_F(SceneBuild, BadKeysAndFilesNameTheKey) {
  const fs::path dir = kScenes;
  EXPECT_NE(error_of(liver_scene(R"({"build": "volumes/abdomen_phantom.nii.gz", "label": "liver", "colour": 1})"), dir)
                .find("colour: unknown key"), std::string::npos);
  EXPECT_NE(error_of(liver_scene(R"({"build": "volumes/missing.nii.gz", "label": 1})"), dir)
                .find("tissues[0].mesh.build: file not found"), std::string::npos);
  const std::string absent = error_of(liver_scene(R"({"build": "volumes/abdomen_phantom.nii.gz", "label": 9})"), dir);
  EXPECT_NE(absent.find("label 9 is not in the volume (labels present: 1, 2)"), std::string::npos) << absent;
  EXPECT_NE(absent.find("abdomen_phantom.nii.gz"), std::string::npos) << absent;
  EXPECT_NE(error_of(liver_scene(R"({"build": "volumes/abdomen_phantom.nii.gz"})"), dir).find("needs \"label\""),
            std::string::npos);
  // A name the volume does not give, with no class map.
  EXPECT_NE(error_of(liver_scene(R"({"build": "volumes/abdomen_phantom.nii.gz", "label": "liver"})"), dir)
                .find("no segment is named \"liver\""), std::string::npos);
}

TEST_F(SceneBuild, WithoutTheBuilderTheSceneSaysWhy) {
  set_volume_mesh_builder(nullptr);
  const std::string e = error_of(liver_scene(R"({"build": "volumes/abdomen_phantom.nii.gz", "label": 1})"), kScenes);
  register_scene_mesh_builder();
  EXPECT_NE(e.find("built without the modelling module"), std::string::npos) << e;
}

}  // namespace
}  // namespace trocar

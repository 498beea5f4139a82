// Pinned state hashes of every shipped scene (after Box2D's test_determinism): `trocar run` of
// each scene for its whole duration must end in exactly these bits, on the SIMD path and on the
// portable one (TROCAR_SIMD=off). A change to any of them is a change of behaviour: if it is
// intended, say so in the commit and update the table (docs/architecture.md, "Determinism").
//
// The two paths sum in different orders, so each has its own hash. The hashes hold for g++ on
// x86-64 with optimisation (the build CI and users make); another compiler or -O0 may contract
// multiply-adds differently inside the AVX2 kernels, so there the test skips and says why.
#include <gtest/gtest.h>

#include <string>

#include "support/run_program.h"

namespace trocar {
namespace {

struct PinnedScene {
  const char* file;      ///< under scenes/
  const char* simd;      ///< hash on the AVX2+FMA path
  const char* portable;  ///< hash with TROCAR_SIMD=off (and on machines without AVX2+FMA)
};

constexpr PinnedScene kScenes[] = {
    {"built_liver.json", "cff7235038b17743", "0eb4aa5f6cbc32d4"},
    {"grasp_lift.json", "8934156d84fd3fc1", "17300703db299817"},
    {"hernia.json", "4caabe91d2ee9a26", "6c17a8a9b913f7ef"},
    {"probe_press_slide.json", "127a077e261cc114", "bc9acc8997828d6a"},
    {"stab.json", "72c21be1d6ec50f4", "6732c2561bebecc3"},
};

/// The hash `trocar run` printed ("... hash 0123456789abcdef"), or "" when it printed none.
std::string printed_hash(const std::string& output) {
  const std::size_t at = output.rfind("hash ");
  return at == std::string::npos ? std::string() : output.substr(at + 5, 16);
}

bool has_avx2_fma() {
#if defined(__x86_64__) && defined(__GNUC__)
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

bool pinned_toolchain() {
#if defined(__GNUC__) && !defined(__clang__) && defined(__OPTIMIZE__) && defined(__x86_64__)
  return true;
#else
  return false;
#endif
}

std::string run_scene(const PinnedScene& scene, bool portable) {
  const std::string env = portable ? "TROCAR_SIMD=off " : "env -u TROCAR_SIMD ";
  const test::RunResult r =
      test::run_program(env + TROCAR_CLI, std::string("run ") + TROCAR_SCENES_DIR + "/" + scene.file);
  EXPECT_EQ(r.exit_code, 0) << scene.file << ":\n" << r.output;
  return printed_hash(r.output);
}

TEST(Determinism, ShippedScenesEndInTheirPinnedHashOnThePortablePath) {
  if (!pinned_toolchain()) GTEST_SKIP() << "hashes are pinned for optimised g++ x86-64 builds";
  for (const PinnedScene& scene : kScenes) EXPECT_EQ(run_scene(scene, true), scene.portable) << scene.file;
}

TEST(Determinism, ShippedScenesEndInTheirPinnedHashOnTheSimdPath) {
  if (!pinned_toolchain()) GTEST_SKIP() << "hashes are pinned for optimised g++ x86-64 builds";
  // Without AVX2+FMA the program takes the portable path whatever it is asked.
  for (const PinnedScene& scene : kScenes)
    EXPECT_EQ(run_scene(scene, false), has_avx2_fma() ? scene.simd : scene.portable) << scene.file;
}

}  // namespace
}  // namespace trocar

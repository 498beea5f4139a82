// The "suction" key of an instrument (a suction-irrigator's flows and radii) and the
// "suction-irrigator" generator: defaults, overrides, none without the key, errors naming the key.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "trocar/core/error.h"
#include "trocar/scene/scene.h"

namespace trocar {
namespace {

/// One generated cannula; `extra` is spliced into the instrument object, `mesh_extra` into its mesh.
std::string cannula_scene(const std::string& extra, const std::string& mesh_extra = "") {
  return R"({"schema": 1, "tissues": [{"mesh": {"generate": "icosphere", "radius": 0.01, "subdivisions": 1}}],
    "instruments": [{"mesh": {"generate": "suction-irrigator")" + mesh_extra + R"(},
                     "motion": {"keyframes": [{"t": 0, "position": [0, 0, 0.05]}]})" + extra + "}]}";
}

SuctionSpec suction_of(const std::string& extra) {
  return parse_scene(cannula_scene(extra), "scene.json", ".").world.instruments[0].suction;
}

std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "scene.json", ".");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(SuctionKey, TrueIsTheFiveMillimetreCannulaAndNoKeyIsNone) {
  const SuctionSpec d = suction_of(R"(, "suction": true)");
  EXPECT_NEAR(d.suction_flow, 1.0 / 60 * 1e-3, 1e-18);    // 1 L/min
  EXPECT_NEAR(d.irrigation_flow, 0.6 / 60 * 1e-3, 1e-18); // 0.6 L/min
  EXPECT_EQ(d.suction_radius, 0.005);
  EXPECT_EQ(d.smoke_radius, 0.02);
  EXPECT_EQ(d.irrigation_reach, 0.05);
  EXPECT_EQ(d.jet_radius, 0.003);
  EXPECT_TRUE(d.suction() && d.irrigation());
  // The generated cannula has no valves without the key, as a hook-probe has no electrode without
  // "electrode"; nor with false.
  for (const char* extra : {"", R"(, "suction": false)"}) {
    const SuctionSpec none = suction_of(extra);
    EXPECT_EQ(none.suction_flow, 0.0) << extra;
    EXPECT_EQ(none.irrigation_flow, 0.0) << extra;
    EXPECT_FALSE(none.any()) << extra;
  }
}

TEST(SuctionKey, AnObjectOverridesTheDefaultsKeyByKey) {
  const SuctionSpec s = suction_of(R"(, "suction": {"suction_flow": 2e-5, "suction_radius": 0.004,
      "smoke_radius": 0.03, "irrigation_flow": 0, "irrigation_reach": 0.04, "jet_radius": 0.002})");
  EXPECT_EQ(s.suction_flow, 2e-5);
  EXPECT_EQ(s.suction_radius, 0.004);
  EXPECT_EQ(s.smoke_radius, 0.03);
  EXPECT_EQ(s.irrigation_flow, 0.0);  // suction only
  EXPECT_EQ(s.irrigation_reach, 0.04);
  EXPECT_EQ(s.jet_radius, 0.002);
  EXPECT_TRUE(s.suction());
  EXPECT_FALSE(s.irrigation());
  const SuctionSpec one = suction_of(R"(, "suction": {"jet_radius": 0.004})");
  EXPECT_EQ(one.jet_radius, 0.004);
  EXPECT_EQ(one.suction_radius, 0.005);  // the rest as true's
  EXPECT_NEAR(one.suction_flow, 1.0 / 60 * 1e-3, 1e-18);
}

TEST(SuctionKey, BadValuesNameTheKey) {
  EXPECT_EQ(error_of(cannula_scene(R"(, "suction": {"suction_flow": -1e-5})")),
            "scene.json: instruments[0].suction.suction_flow: must be >= 0");
  EXPECT_EQ(error_of(cannula_scene(R"(, "suction": {"irrigation_flow": -1})")),
            "scene.json: instruments[0].suction.irrigation_flow: must be >= 0");
  EXPECT_EQ(error_of(cannula_scene(R"(, "suction": {"jet_radius": 0})")),
            "scene.json: instruments[0].suction.jet_radius: must be > 0");
  EXPECT_EQ(error_of(cannula_scene(R"(, "suction": {"smoke_radius": -0.01})")),
            "scene.json: instruments[0].suction.smoke_radius: must be > 0");
  EXPECT_EQ(error_of(cannula_scene(R"(, "suction": {"suction_radius": "wide"})")),
            "scene.json: instruments[0].suction.suction_radius: must be a number, not a string");
  EXPECT_NE(error_of(cannula_scene(R"(, "suction": {"flow": 1})")).find("instruments[0].suction.flow: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of(cannula_scene(R"(, "suction": 1)")).find("instruments[0].suction: "), std::string::npos);
  // Non-finite: JSON has no infinity, and an overflowing number is a parse error.
  EXPECT_NE(error_of(cannula_scene(R"(, "suction": {"suction_flow": 1e999})")).find("invalid JSON"), std::string::npos);
}

TEST(SuctionKey, TheGeneratorBuildsTheRoundedCannula) {
  const Scene scene = parse_scene(cannula_scene(R"(, "top_vertex": "auto", "suction": true)",
                                                R"(, "segments": 12, "round_rings": 2, "shaft_length": 0.3)"),
                                  "scene.json", ".");
  const InstrumentBody& body = scene.world.instruments[0];
  EXPECT_EQ(body.tool, "suction-irrigator");
  const TriMesh& m = body.instrument.local_mesh();
  EXPECT_EQ(m.positions.size(), (2u + 2) * 12 + 2);  // (n + 2)s + 2
  EXPECT_EQ(m.triangles.size(), 2u * (2 + 2) * 12);  // 2(n + 2)s
  Real top = 0;
  for (const Vec3& p : m.positions) top = std::max(top, p.z());
  EXPECT_NEAR(top, 0.3, 1e-12);
  EXPECT_NE(error_of(cannula_scene("", R"(, "tip_round": 0.003)")).find("suction-irrigator tip_round"), std::string::npos);
  EXPECT_NE(error_of(cannula_scene("", R"(, "round_rings": 0)")).find("instruments[0].mesh.round_rings"),
            std::string::npos);
}

}  // namespace
}  // namespace trocar

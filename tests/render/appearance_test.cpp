// Per-object appearance, tacks and the headless task panel in rendered pixels (docs/render.md
// "Appearance", "Tacks", "The task panel"). TROCAR_TEST_FRAMES=DIR writes the frames as PNGs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "trocar/render/frame_recorder.h"
#include "trocar/render/offscreen.h"
#include "trocar/render/renderer.h"
#include "trocar/scene/scene.h"

namespace trocar {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;

/// Saves an image for a person to look at when TROCAR_TEST_FRAMES names a folder.
void keep(const Image& img, const char* name) {
  const char* dir = std::getenv("TROCAR_TEST_FRAMES");
  if (!dir || !*dir) return;
  std::filesystem::create_directories(dir);
  write_png((std::filesystem::path(dir) / name).c_str(), img);
}

/// Flat sheets in planes z = const, fixed, no gravity: nothing moves, so a snapshot is the rest.
/// Each entry: half-size (m), height z (m).
std::unique_ptr<Simulation> sheets(std::initializer_list<std::pair<double, double>> list, int cells = 8) {
  std::string tissues;
  for (const auto& [half, z] : list) {
    if (!tissues.empty()) tissues += ",";
    tissues += R"({"mesh": {"generate": "sheet", "width": )" + std::to_string(2 * half) + R"(, "height": )" +
               std::to_string(2 * half) + R"(, "nx": )" + std::to_string(cells) + R"(, "ny": )" +
               std::to_string(cells) + R"(}, "translate": [0, 0, )" + std::to_string(z) +
               R"(], "fixed": {"inside_box": {"min": [-1, -1, -1], "max": [1, 1, 1]}}})";
  }
  Scene scene = parse_scene(R"({"schema": 1, "gravity": [0, 0, 0], "tissues": [)" + tissues + "]}", "look.json", ".");
  return std::make_unique<Simulation>(std::move(scene.world), scene.settings);
}

CameraView orbit(double distance, double pitch_deg, int w = kWidth, int h = kHeight) {
  CameraSpec c;
  c.kind = CameraKind::kOrbit;
  c.target = Vec3::Zero();
  c.distance = distance;
  c.pitch_deg = pitch_deg;
  c.yaw_deg = 20;
  c.fov_deg = 40;
  return make_camera_view(c, double(w) / h);
}

RenderOptions plain_options() {
  RenderOptions o;
  o.contacts = o.forces = o.gauge = false;
  o.vignette = 0;
  o.light_range = 1.0;
  return o;
}

Appearance look(float r, float g, float b, SurfacePattern pattern = SurfacePattern::kPlain, float opacity = 1) {
  Appearance a;
  a.given = true;
  a.colour = {r, g, b};
  a.pattern = pattern;
  a.opacity = opacity;
  return a;
}

Image draw(const Simulation& sim, const SceneLook& looks, const CameraView& cam, const ViewSnapshot& snap,
           const RenderOptions& o = plain_options(), int w = kWidth, int h = kHeight) {
  OffscreenContext ctx(w, h, 1);
  Renderer renderer(sim.world(), looks);
  ctx.bind();
  renderer.draw(snap, cam, o, w, h);
  Image img;
  ctx.read(img);
  return img;
}

Image draw(const Simulation& sim, const SceneLook& looks, const CameraView& cam) {
  ViewSnapshot snap;
  capture_view(sim, snap);
  return draw(sim, looks, cam, snap);
}

int channel_gap(const std::uint8_t* a, const std::uint8_t* b) {
  int d = 0;
  for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(a[k]) - int(b[k])));
  return d;
}

TEST(Appearance, PlainColourReachesThePixelsUnderTheHeadlight) {
  auto sim = sheets({{0.03, 0}});
  const CameraView cam = orbit(0.2, 30);
  const Appearance a = look(0.2f, 0.5f, 0.8f);
  const Image img = draw(*sim, SceneLook{{}, {a}, {}}, cam);
  keep(img, "plain.png");
  const Eigen::Vector3d px = cam.project(Vec3::Zero(), kWidth, kHeight);
  const std::uint8_t* p = img.at(int(px.x()), int(px.y()));
  // The shader's light at the sheet's centre (docs/render.md "What a frame shows"): albedo ·
  // (0.06 + 0.94·n·l) + 0.85·(n·l)^80 + 0.12·(n·l)^10, times 1/(1 + d²/range²), gamma 2.2.
  const Vec3 to_eye = cam.eye;  // from the origin
  const double d = to_eye.norm(), ndl = std::abs(to_eye.z()) / d;
  EXPECT_NEAR(ndl, 0.5, 1e-9);  // pitch 30°: the eye 60° off the sheet's normal
  const double falloff = 1 / (1 + d * d / (1.0 * 1.0));
  const double spec = 0.85 * std::pow(ndl, 80) + 0.12 * std::pow(ndl, 10);
  for (int k = 0; k < 3; ++k) {
    const double linear = (a.colour[std::size_t(k)] * (0.06 + 0.94 * ndl) + spec) * falloff;
    const double expected = 255 * std::pow(std::clamp(linear, 0.0, 1.0), 1 / 2.2);
    EXPECT_NEAR(double(p[k]), expected, 2.5) << "channel " << k;
  }
  // Without an appearance the same pixel is the default tissue: red above blue.
  const Image plain_default = draw(*sim, SceneLook{}, cam);
  const std::uint8_t* q = plain_default.at(int(px.x()), int(px.y()));
  EXPECT_GT(int(q[0]), int(q[2]) + 30);
  EXPECT_GT(int(p[2]), int(p[0]) + 60);
}

TEST(Appearance, TranslucentSheetBlendsWithWhatIsBehindIt) {
  // A pink sheet 1 cm above a blue one; the pink at opacity 0.4.
  auto sim = sheets({{0.03, 0.01}, {0.05, 0}});
  const CameraView cam = orbit(0.2, 50);
  const Appearance pink = look(0.9f, 0.5f, 0.6f), blue = look(0.1f, 0.2f, 0.9f);
  const auto with_opacity = [](Appearance a, float opacity) {
    a.opacity = opacity;
    return a;
  };
  const Image front = draw(*sim, SceneLook{{}, {pink, with_opacity(blue, 0)}, {}}, cam);
  const Image back = draw(*sim, SceneLook{{}, {with_opacity(pink, 0), blue}, {}}, cam);
  const Image blend = draw(*sim, SceneLook{{}, {with_opacity(pink, 0.4f), blue}, {}}, cam);
  keep(blend, "translucent.png");
  const Eigen::Vector3d px = cam.project(Vec3(0, 0, 0.01), kWidth, kHeight);
  const int x = int(px.x()), y = int(px.y());
  ASSERT_GT(channel_gap(front.at(x, y), back.at(x, y)), 80);  // two clearly different colours
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(double(blend.at(x, y)[k]), 0.4 * front.at(x, y)[k] + 0.6 * back.at(x, y)[k], 2.0) << "channel " << k;
  // A translucent sheet behind an opaque one is hidden: depth still tests in the translucent pass.
  const Image hidden = draw(*sim, SceneLook{{}, {pink, with_opacity(blue, 0.5f)}, {}}, cam);
  EXPECT_LE(channel_gap(hidden.at(x, y), front.at(x, y)), 1);
  // The id pass ignores appearances: both sheets are flat tissue red.
  ViewSnapshot snap;
  capture_view(*sim, snap);
  RenderOptions id = plain_options();
  id.id_colors = true;
  const Image ids = draw(*sim, SceneLook{{}, {with_opacity(pink, 0.4f), blue}, {}}, cam, snap, id);
  EXPECT_EQ(int(ids.at(x, y)[0]), 255);
  EXPECT_EQ(int(ids.at(x, y)[2]), 0);
}

TEST(Appearance, WeaveShowsTheBackgroundThroughItsHoles) {
  // A 6 cm weave 5 mm above a red sheet, seen nearly from above.
  constexpr int w = 480, h = 360;
  auto sim = sheets({{0.03, 0.005}, {0.06, 0}});
  const CameraView cam = orbit(0.12, 75, w, h);
  const Appearance red = look(0.8f, 0.1f, 0.1f);
  ViewSnapshot snap;
  capture_view(*sim, snap);
  const RenderOptions o = plain_options();
  const Image weave = draw(*sim, SceneLook{{}, {look(0.92f, 0.92f, 0.88f, SurfacePattern::kWeave), red}, {}}, cam, snap, o, w, h);
  const Image solid = draw(*sim, SceneLook{{}, {look(0.92f, 0.92f, 0.88f), red}, {}}, cam, snap, o, w, h);
  const Image without = draw(*sim, SceneLook{{}, {look(0.9f, 0.9f, 0.9f, SurfacePattern::kPlain, 0), red}, {}}, cam, snap, o, w, h);
  keep(weave, "weave.png");
  // The weave's pixels: where the solid sheet differs from the scene without it.
  std::size_t area = 0, holes = 0, light = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (channel_gap(solid.at(x, y), without.at(x, y)) < 40) continue;
      ++area;
      if (channel_gap(weave.at(x, y), without.at(x, y)) <= 3) ++holes;
      if (int(weave.at(x, y)[1]) > int(without.at(x, y)[1]) + 40) ++light;  // a pale filament over the red
    }
  ASSERT_GT(area, std::size_t(w * h) / 10);
  const double hole_fraction = double(holes) / double(area), thread_fraction = double(light) / double(area);
  std::printf("weave: %zu px, %.1f %% show the sheet behind, %.1f %% pale filament\n", area, 100 * hole_fraction,
              100 * thread_fraction);
  // Filaments 0.3 of the period wide both ways: (1 − 0.3)² ≈ 0.49 of the area open, less the
  // antialiased filament edges.
  EXPECT_GT(hole_fraction, 0.25);
  EXPECT_LT(hole_fraction, 0.65);
  EXPECT_GT(thread_fraction, 0.25);
}

TEST(Appearance, HoldingAttachmentIsDrawnAsATitaniumTack) {
  // A green mesh sheet 1 mm over a blue wall; a tack through both at (5 mm, −4 mm).
  auto sim = sheets({{0.03, 0.001}, {0.04, 0}}, 12);
  const CameraView cam = orbit(0.1, 60);
  const SceneLook looks{{}, {look(0.1f, 0.7f, 0.2f), look(0.15f, 0.2f, 0.8f)}, {}};
  ViewSnapshot before;
  capture_view(*sim, before);
  EXPECT_TRUE(before.tacks.empty());
  const Vec3 at(0.005, -0.004, 0.001);
  // The triangles under `at` on each sheet (the sheets are flat: barycentric in xy).
  const auto surface_point = [&](std::uint32_t tissue) {
    const TissueBody& t = *sim->world().tissues[tissue];
    for (std::uint32_t f = 0; f < t.settings.triangles.size(); ++f) {
      const Triangle& tri = t.settings.triangles[f];
      const Vec3 a = t.state.positions[tri[0]], b = t.state.positions[tri[1]], c = t.state.positions[tri[2]];
      const double area = (b - a).cross(c - a).z();
      const double wa = (b - at).cross(c - at).z() / area, wb = (c - at).cross(a - at).z() / area;
      if (wa >= 0 && wb >= 0 && wa + wb <= 1) return SurfacePoint{tissue, f, Vec3(wa, wb, 1 - wa - wb)};
    }
    return SurfacePoint{tissue, 0, Vec3(1, 0, 0)};
  };
  AttachmentSpec spec;
  spec.a = surface_point(0);
  spec.b = surface_point(1);
  ASSERT_NE(sim->attach(spec), std::size_t(-1));
  ViewSnapshot after;
  capture_view(*sim, after);
  ASSERT_EQ(after.tacks.size(), 1u);
  EXPECT_LT((after.tacks[0].point - at).norm(), 1e-12);
  EXPECT_NEAR(std::abs(after.tacks[0].normal.z()), 1.0, 1e-12);
  const Image plain = draw(*sim, looks, cam, before);
  const Image tacked = draw(*sim, looks, cam, after);
  keep(tacked, "tack.png");
  const Eigen::Vector3d c = cam.project(at, kWidth, kHeight);
  // The tack's 4 mm, seen from 10 cm through a 40° field 240 px high: ≈ 26 px across.
  const double px_per_m = kHeight / (2 * 0.1 * std::tan(20.0 * 3.14159265358979 / 180));
  std::size_t changed = 0, near = 0, grey = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      if (channel_gap(plain.at(x, y), tacked.at(x, y)) < 20) continue;
      ++changed;
      if (std::hypot(x + 0.5 - c.x(), y + 0.5 - c.y()) < 0.004 * px_per_m) ++near;
      const std::uint8_t* p = tacked.at(x, y);
      if (std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) < 30) ++grey;
    }
  std::printf("tack: %zu px changed, %zu within 4 mm of the attachment, %zu grey\n", changed, near, grey);
  EXPECT_GT(changed, 40u);
  EXPECT_EQ(near, changed);
  EXPECT_GE(double(grey), 0.8 * double(changed));
  // The id pass draws no tacks.
  RenderOptions id = plain_options();
  id.id_colors = true;
  EXPECT_EQ(draw(*sim, looks, cam, before, id).rgb, draw(*sim, looks, cam, after, id).rgb);
}

TEST(Appearance, TackMeshIsFourMillimetresLongAndAcross) {
  const TriMesh m = make_tack_mesh();
  Vec3 lo = Vec3::Constant(1), hi = Vec3::Constant(-1);
  for (const Vec3& p : m.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  EXPECT_NEAR(hi.x() - lo.x(), 4e-3, 1e-4);  // coil 3.5 mm + wire 0.5 mm
  EXPECT_NEAR(hi.y() - lo.y(), 4e-3, 1e-4);
  // 4 mm of coil centreline plus the wire's thickness (the end ring leans with the coil's pitch).
  EXPECT_NEAR(hi.z() - lo.z(), 4.5e-3, 1e-5);
  EXPECT_NEAR(hi.z(), 0.75e-3, 1e-9);          // the head 0.5 mm above the surface, plus the wire
  EXPECT_GT(m.signed_volume(), 0);             // closed tubes, outward
}

TaskView sample_task() {
  TaskView t;
  t.title = "TAPP repair";
  t.steps = {{"sac reduced", StepState::kDone, "94 % behind the wall", 12.5},
             {"mesh placed", StepState::kActive, "overlap 2.1 cm of 3 cm", -1},
             {"mesh fixed", StepState::kPending, "", -1}};
  t.events = {{8.2, true, "epigastric vessels grasped"}, {14.0, false, "mesh unrolled"}};
  return t;
}

TEST(TaskPanel, HeadlessFramesDrawThePanelTopRight) {
  if (!FrameRecorder::draws_task_panel()) GTEST_SKIP() << "built without Dear ImGui: no headless task panel";
  auto sim = sheets({{0.03, 0}});
  const auto record = [&](const char* dir_name, const TaskView* task) {
    FrameSettings s;
    s.dir = std::filesystem::temp_directory_path() / dir_name;
    std::filesystem::remove_all(s.dir);
    s.width = kWidth;
    s.height = kHeight;
    s.samples = 1;
    s.camera = select_camera({}, sim->world(), "orbit");
    s.options = plain_options();
    FrameRecorder rec(sim->world(), s);
    rec.on_step(*sim, task);
    Image img = read_png(rec.frame_path(0).c_str());
    std::filesystem::remove_all(s.dir);
    return img;
  };
  const TaskView task = sample_task();
  const Image without = record("trocar_panel_none", nullptr);
  const Image with = record("trocar_panel_task", &task);
  keep(with, "panel.png");
  // The panel: 200 px wide (30 % of the width, at least 200) at x ≥ 320 − 200 − 8, from y = 8.
  std::size_t inside = 0, outside = 0, red_text = 0, green_text = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      if (channel_gap(with.at(x, y), without.at(x, y)) < 10) continue;
      (x >= 112 && x < 312 && y >= 8) ? ++inside : ++outside;
      const std::uint8_t* p = with.at(x, y);
      red_text += p[0] > 200 && p[1] < 130 && p[2] < 130;
      green_text += p[1] > 170 && p[0] < 150 && p[2] < 150;
    }
  std::printf("panel: %zu px changed inside its corner, %zu outside; %zu red, %zu green text px\n", inside, outside,
              red_text, green_text);
  EXPECT_GT(inside, 5000u);
  EXPECT_EQ(outside, 0u);
  EXPECT_GT(red_text, 10u);    // the error event
  EXPECT_GT(green_text, 10u);  // the done step
}

}  // namespace
}  // namespace trocar

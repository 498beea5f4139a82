// Headless frames of a shipped scene checked against its projected geometry (docs/render.md
// "Headless frames").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "raster_mask.h"
#include "support/shared_data.h"
#include "trocar/core/error.h"
#include "trocar/render/frame_recorder.h"
#include "trocar/render/offscreen.h"
#include "trocar/render/renderer.h"
#include "trocar/scene/scene.h"

namespace trocar {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;

struct Fixture {
  Scene scene;
  std::unique_ptr<Simulation> sim;
  CameraView camera;
  explicit Fixture(const char* file) : scene(load_scene(std::string(TROCAR_TEST_SCENES) + "/" + file)) {
    const std::vector<CameraSpec> cameras = scene.cameras;
    sim = std::make_unique<Simulation>(std::move(scene.world), scene.settings);
    camera = make_camera_view(select_camera(cameras, sim->world(), "scope"), double(kWidth) / kHeight);
  }
  void run_to(double t) {
    while (sim->time() < t - 1e-9) sim->step(scene.timestep);
  }
};

Image render(OffscreenContext& ctx, Renderer& r, const ViewSnapshot& snap, const CameraView& cam, RenderOptions o) {
  ctx.bind();
  r.draw(snap, cam, o, ctx.width(), ctx.height());
  Image img;
  ctx.read(img);
  return img;
}

std::uint8_t id_label(const std::uint8_t* p) {
  if (p[0] > 128 && p[1] < 64 && p[2] < 64) return test::kTissue;
  if (p[1] > 128 && p[0] < 64 && p[2] < 64) return test::kInstrument;
  if (p[2] > 128 && p[0] < 64 && p[1] < 64) return test::kRigid;
  return test::kBackground;
}

double luminance(const std::uint8_t* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

/// Pixels labelled alike by both, over the pixels either labels as geometry.
double agreement(const test::LabelImage& mask, const Image& img, bool shaded) {
  std::size_t both = 0, either = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t m = mask.at(x, y);
      const std::uint8_t g = shaded ? (luminance(img.at(x, y)) > 12 ? 1 : 0) : id_label(img.at(x, y));
      const std::uint8_t mm = shaded ? (m != test::kBackground ? 1 : 0) : m;
      if (mm == 0 && g == 0) continue;
      ++either;
      if (mm == g) ++both;
    }
  return either ? double(both) / double(either) : 0;
}

TEST(Render, IdPassMatchesProjectedGeometryOfEveryShippedScene) {
  for (const char* file : {"probe_press_slide.json", "hernia.json", "grasp_lift.json", "stab.json"}) {
    SCOPED_TRACE(file);
    Fixture f(file);
    OffscreenContext ctx(kWidth, kHeight, 1);
    Renderer renderer(f.sim->world());
    ViewSnapshot snap;
    capture_view(*f.sim, snap);
    RenderOptions o;
    o.id_colors = true;
    const Image img = render(ctx, renderer, snap, f.camera, o);
    const test::LabelImage mask = test::project_labels(f.sim->world(), snap, f.camera, kWidth, kHeight);
    std::size_t tissue = 0, instrument = 0;
    for (std::uint8_t l : mask.label) tissue += l == test::kTissue, instrument += l == test::kInstrument;
    // The scene's scope sees both the organ and the instrument, each over a fair part of the frame.
    EXPECT_GT(tissue, std::size_t(kWidth * kHeight) / 40);
    EXPECT_GT(instrument, 40u);
    const double a = agreement(mask, img, false);
    std::printf("%s: id pass agrees with the projected geometry on %.2f %% of its pixels\n", file, 100 * a);
    EXPECT_GE(a, 0.95);
  }
}

TEST(Render, ShadedFrameCoversTheGeometryAndIsNotFlat) {
  Fixture f("probe_press_slide.json");
  OffscreenContext ctx(kWidth, kHeight, 4);
  Renderer renderer(f.sim->world());
  ViewSnapshot snap;
  capture_view(*f.sim, snap);
  RenderOptions o;
  o.contacts = o.forces = o.gauge = false;
  o.vignette = 0;
  const Image img = render(ctx, renderer, snap, f.camera, o);
  const test::LabelImage mask = test::project_labels(f.sim->world(), snap, f.camera, kWidth, kHeight);
  const double cover = agreement(mask, img, true);
  std::printf("shaded frame covers the projected geometry on %.2f %% of its pixels\n", 100 * cover);
  EXPECT_GE(cover, 0.95);
  // Lighting varies across the organ: a headlight gives a bright highlight and darker flanks.
  double sum = 0, sum2 = 0, lo = 255, hi = 0;
  std::size_t n = 0;
  double red = 0, green = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      if (mask.at(x, y) != test::kTissue) continue;
      const double l = luminance(img.at(x, y));
      sum += l, sum2 += l * l, ++n;
      lo = std::min(lo, l), hi = std::max(hi, l);
      red += img.at(x, y)[0], green += img.at(x, y)[1];
    }
  ASSERT_GT(n, 1000u);
  const double mean = sum / double(n);
  const double sd = std::sqrt(std::max(0.0, sum2 / double(n) - mean * mean));
  std::printf("organ luminance: mean %.1f, sd %.1f, range %.0f..%.0f\n", mean, sd, lo, hi);
  EXPECT_GT(sd / mean, 0.12) << "mean " << mean << " sd " << sd;
  EXPECT_GT(hi - lo, 100) << lo << " .. " << hi;
  EXPECT_GT(red, 1.3 * green);  // tissue is red, not grey
}

TEST(Render, PressingChangesTheFrameWhereItPresses) {
  Fixture f("probe_press_slide.json");
  OffscreenContext ctx(kWidth, kHeight, 1);
  Renderer renderer(f.sim->world());
  RenderOptions o;
  o.contacts = o.forces = o.gauge = false;
  o.vignette = 0;
  // The rest frame: the same scene at the same time with the probe held far away, so gravity's
  // sag is in both and only the press differs.
  Fixture away("probe_press_slide.json");
  const Pose far_pose = Pose::from_euler_deg(Vec3(0, 0, 0.5), Vec3::Zero());
  while (away.sim->time() < 0.95 - 1e-9) {
    away.sim->place_instrument(0, far_pose, 0);
    away.sim->step(away.scene.timestep);
  }
  ViewSnapshot rest, press;
  capture_view(*away.sim, rest);
  const Image a = render(ctx, renderer, rest, f.camera, o);
  f.run_to(0.95);  // the probe at its deepest, 2.25 cm down
  capture_view(*f.sim, press);
  ASSERT_GT(press.contacts.size(), 0u);
  const Image b = render(ctx, renderer, press, f.camera, o);
  const test::LabelImage ma = test::project_labels(f.sim->world(), rest, f.camera, kWidth, kHeight);
  const test::LabelImage mb = test::project_labels(f.sim->world(), press, f.camera, kWidth, kHeight);
  const Eigen::Vector3d c = f.camera.project(press.instruments[0].contact_centre, kWidth, kHeight);
  // Tissue pixels in both frames (the instrument's own motion aside) that changed.
  std::size_t changed = 0, near = 0;
  const double radius = 0.25 * kHeight;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      if (ma.at(x, y) != test::kTissue || mb.at(x, y) != test::kTissue) continue;
      int d = 0;
      for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(a.at(x, y)[k]) - int(b.at(x, y)[k])));
      if (d < 24) continue;
      ++changed;
      if (std::hypot(x + 0.5 - c.x(), y + 0.5 - c.y()) < radius) ++near;
    }
  std::printf("pressing changed %zu tissue pixels, %zu of them within %.0f px of the contact\n", changed, near, radius);
  EXPECT_GT(changed, 60u);
  EXPECT_GE(double(near), 0.9 * double(changed)) << near << " of " << changed << " changed pixels near the contact";
}

TEST(Render, FrameRecorderWritesOnePngPerFrameTime) {
  Fixture f("probe_press_slide.json");
  FrameSettings s;
  s.dir = std::filesystem::temp_directory_path() / "trocar_render_test_frames";
  std::filesystem::remove_all(s.dir);
  s.fps = 100;
  s.width = 64;
  s.height = 48;
  s.samples = 1;
  s.camera = select_camera(f.scene.cameras, f.sim->world(), "orbit");
  FrameRecorder rec(f.sim->world(), s);
  rec.on_step(*f.sim);
  f.run_to(0.05);
  rec.on_step(*f.sim);
  EXPECT_EQ(rec.frames(), 6u);  // t = 0, 0.01 … 0.05
  EXPECT_TRUE(std::filesystem::exists(rec.frame_path(5)));
  EXPECT_GT(std::filesystem::file_size(rec.frame_path(5)), 100u);
  EXPECT_THROW(select_camera(f.scene.cameras, f.sim->world(), "nope"), Error);
  std::filesystem::remove_all(s.dir);
}

}  // namespace
}  // namespace trocar

namespace trocar {
namespace {

TEST(Render, MeshUvsMapTheScenesTexture) {
  // A 4 × 4 cm sheet in the xy-plane with u along x; its texture is green on the left half and
  // blue on the right. Seen from above, the sheet's left half renders green, its right half blue.
  const auto dir = std::filesystem::temp_directory_path() / "trocar_uv_test";
  std::filesystem::create_directories(dir);
  Image tex;
  tex.width = 64;
  tex.height = 8;
  tex.rgb.resize(64 * 8 * 3);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 64; ++x) {
      std::uint8_t* p = &tex.rgb[3 * std::size_t(y * 64 + x)];
      p[0] = 0, p[1] = x < 32 ? 220 : 0, p[2] = x < 32 ? 0 : 220;
    }
  write_png((dir / "halves.png").c_str(), tex);
  EXPECT_EQ(read_png((dir / "halves.png").c_str()).rgb, tex.rgb);
  {
    std::ofstream obj(dir / "sheet.obj");
    obj << "v -0.02 -0.02 0\nv 0.02 -0.02 0\nv 0.02 0.02 0\nv -0.02 0.02 0\n"
           "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  }
  const std::string text = R"({"schema": 1, "gravity": [0, 0, 0],
    "tissues": [{"name": "sheet", "mesh": "sheet.obj", "texture": "halves.png",
                 "fixed": {"indices": [0, 1, 2, 3]}}],
    "camera": {"port": [0, 0, 0.2], "target": [0, 0, 0], "insertion": 0.1, "up": [0, 1, 0], "fov_deg": 40}})";
  Scene scene = parse_scene(text, "uv.json", dir);
  ASSERT_EQ(scene.textures.size(), 1u);
  const std::vector<CameraSpec> cameras = scene.cameras;
  const std::vector<std::filesystem::path> textures = scene.textures;
  Simulation sim(std::move(scene.world), scene.settings);
  ASSERT_EQ(sim.world().tissues[0]->texcoords.size(), 6u);
  OffscreenContext ctx(kWidth, kHeight, 1);
  Renderer renderer(sim.world(), textures);
  ViewSnapshot snap;
  capture_view(sim, snap);
  const CameraView cam = make_camera_view(select_camera(cameras, sim.world(), "scope"), double(kWidth) / kHeight);
  RenderOptions o;
  o.vignette = 0;
  o.gauge = false;
  const Image img = render(ctx, renderer, snap, cam, o);
  const Eigen::Vector3d left = cam.project(Vec3(-0.01, 0, 0), kWidth, kHeight);
  const Eigen::Vector3d right = cam.project(Vec3(0.01, 0, 0), kWidth, kHeight);
  const std::uint8_t* l = img.at(int(left.x()), int(left.y()));
  const std::uint8_t* r = img.at(int(right.x()), int(right.y()));
  // Seen head-on under the headlight the sheet also carries a white highlight, added to both.
  EXPECT_GT(int(l[1]), int(l[2]) + 40) << int(l[0]) << " " << int(l[1]) << " " << int(l[2]);
  EXPECT_GT(int(r[2]), int(r[1]) + 40) << int(r[0]) << " " << int(r[1]) << " " << int(r[2]);
  // A texture on a mesh without UVs, or a missing image, is a scene error naming the key.
  EXPECT_THROW(parse_scene(R"({"schema": 1, "tissues": [{"mesh": {"generate": "icosphere", "radius": 0.02}, "texture": "halves.png"}]})",
                           "uv.json", dir), Error);
  EXPECT_THROW(parse_scene(R"({"schema": 1, "tissues": [{"mesh": "sheet.obj", "texture": "none.png"}]})",
                           "uv.json", dir), Error);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace trocar


namespace trocar {
namespace {

// Organs the shipped scenes do not have, framed by the default camera: each fills a fair part of
// the frame and the id pass still matches the projected geometry.
TEST(Render, DefaultCameraFramesUnseenSharedOrgans) {
  const std::pair<const char*, double> organs[] = {{"liver_sofa_smooth.obj", 0.01},
                                                   {"liver_bodyparts3d_FMA7197.obj", 0.001},
                                                   {"stomach_bodyparts3d_FMA7148.obj", 0.001},
                                                   {"kidney_right_bodyparts3d_FMA7204.obj", 0.001},
                                                   {"gallbladder_lapgym.stl", 0.01}};
  int rendered = 0;
  for (const auto& [file, scale] : organs) {
    const auto path = test::shared_mesh_path(file);
    if (!path) continue;
    SCOPED_TRACE(file);
    const std::string text = R"({"schema": 1, "gravity": [0, 0, 0], "tissues": [{"mesh": ")" + path->string() +
                             R"(", "scale": )" + std::to_string(scale) + R"(, "repair": true}]})";
    Scene scene = parse_scene(text, "organ.json", ".");
    Simulation sim(std::move(scene.world), scene.settings);
    const CameraView cam = make_camera_view(select_camera({}, sim.world(), "scope"), double(kWidth) / kHeight);
    OffscreenContext ctx(kWidth, kHeight, 1);
    Renderer renderer(sim.world());
    ViewSnapshot snap;
    capture_view(sim, snap);
    RenderOptions o;
    o.id_colors = true;
    const Image img = render(ctx, renderer, snap, cam, o);
    const test::LabelImage mask = test::project_labels(sim.world(), snap, cam, kWidth, kHeight);
    std::size_t tissue = 0;
    for (std::uint8_t l : mask.label) tissue += l == test::kTissue;
    const double a = agreement(mask, img, false);
    std::printf("%s: %.1f %% of the frame, id pass agreement %.2f %%\n", file, 100.0 * double(tissue) / (kWidth * kHeight),
                100 * a);
    EXPECT_GT(tissue, std::size_t(kWidth * kHeight) / 20);
    EXPECT_GE(a, 0.95);
    ++rendered;
  }
  if (rendered == 0) GTEST_SKIP() << test::shared_absent("liver_sofa_smooth.obj");
}

}  // namespace
}  // namespace trocar

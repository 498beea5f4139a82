#include "mesh_build_command.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "trocar/core/error.h"

#if TROCAR_HAVE_MODELLING
#include <nlohmann/json.hpp>

#include "trocar/modelling/build_cache.h"
#include "trocar/modelling/organ_builder.h"
#include "trocar/modelling/phantoms.h"
#endif

namespace trocar::cli {
namespace {

struct BuildArgs {
  std::string volume;
  std::string output;
  std::string label;
  std::vector<double> threshold;
  std::string class_map;
  int layer = -1;
  std::size_t target_triangles = 6000;
  int smooth_iterations = 20;
  double passband = 0.01;
  double presmooth_mm = 0;
  double close_mm = 0;
  bool all_components = false;
  std::size_t min_component_voxels = 8;
  int stride = 0;
  int remesh = 3;
  std::size_t texture_size = 256;
  bool no_texture = false;
  std::string report;
  bool quiet = false;
};

struct PhantomArgs {
  std::string name;
  std::string output;
  double voxel_mm = 1;
  std::string class_map;
};

#if TROCAR_HAVE_MODELLING

/// A one-line progress bar on stderr when it is a terminal; stage names otherwise.
class ProgressBar {
 public:
  explicit ProgressBar(bool quiet) : quiet_(quiet), tty_(isatty(STDERR_FILENO) != 0) {}
  ~ProgressBar() { finish(); }
  void operator()(const std::string& stage, double fraction) {
    if (quiet_) return;
    if (!tty_) {
      if (stage != stage_) std::fprintf(stderr, "trocar: %s\n", stage.c_str());
      stage_ = stage;
      return;
    }
    const int filled = static_cast<int>(fraction * 30 + 0.5);
    std::fprintf(stderr, "\r  %-10s [%-30s] %3d%%", stage.c_str(), std::string(static_cast<std::size_t>(filled), '#').c_str(),
                 static_cast<int>(fraction * 100 + 0.5));
    std::fflush(stderr);
    stage_ = stage;
    shown_ = true;
  }
  void finish() {
    if (shown_) std::fprintf(stderr, "\r%60s\r", "");
    shown_ = false;
  }

 private:
  bool quiet_, tty_;
  bool shown_ = false;
  std::string stage_;
};

void check_writable_dir(const std::string& file) {
  const std::filesystem::path parent = std::filesystem::absolute(file).parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(parent, ec)) throw FileError(file, FileLocation::none(), "its folder does not exist");
}

void run_build(const BuildArgs& a) {
  OrganBuildOptions options;
  if (!a.label.empty() && !a.threshold.empty()) throw Error("give --label or --threshold, not both");
  if (a.label.empty() && a.threshold.empty()) throw Error("give --label VALUE|NAME or --threshold LOW [HIGH]");
  options.query.label = a.label;
  if (!a.threshold.empty()) options.query.threshold_low = a.threshold[0];
  if (a.threshold.size() > 1) options.query.threshold_high = a.threshold[1];
  options.query.layer = a.layer;
  if (!a.class_map.empty()) options.query.class_map = read_class_map(a.class_map);
  options.surface.target_triangles = a.target_triangles;
  options.surface.smooth_iterations = a.smooth_iterations;
  options.surface.smooth_passband = a.passband;
  options.surface.presmooth_sigma = a.presmooth_mm * 1e-3;
  options.surface.close_radius = a.close_mm * 1e-3;
  options.surface.largest_component_only = !a.all_components;
  options.surface.min_component_voxels = a.min_component_voxels;
  options.surface.extract_stride = a.stride;
  options.surface.remesh_iterations = a.remesh;
  options.texture_chart_pixels = a.no_texture ? 0 : a.texture_size;
  check_writable_dir(a.output);
  if (!a.report.empty()) check_writable_dir(a.report);

  ProgressBar bar(a.quiet);
  bar("read", 0);
  const auto t0 = std::chrono::steady_clock::now();
  const Volume volume = read_volume(a.volume);
  const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const OrganBuild build = build_organ(volume, options, [&bar](const std::string& s, double f) { bar(s, f); });
  bar.finish();
  const auto t1 = std::chrono::steady_clock::now();
  write_organ(build, a.output);
  nlohmann::json report = build_report(build, volume);
  auto& seconds = report.at("seconds");
  seconds["read"] = read_seconds;
  seconds["write"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  seconds["total"] = seconds.at("total").get<double>() + read_seconds + seconds.at("write").get<double>();
  if (!a.report.empty()) {
    std::ofstream out(a.report);
    out << report.dump(2) << "\n";
    if (!out) throw FileError(a.report, FileLocation::none(), "cannot write the report");
  }
  if (!a.quiet) {
    const auto& s = report.at("seconds");
    std::printf("%s: %s -> %s\n", a.volume.c_str(), build.mask.what.c_str(), a.output.c_str());
    std::printf("  triangles %zu (full-resolution surface %zu, extraction stride %d), genus %d, closed, manifold, outward\n",
                build.mesh.triangle_count(), build.surface.raw.triangle_count(), build.surface.stride, build.genus);
    std::printf("  volume %.2f cm3 (voxels %.2f cm3, %+.2f %%)\n", build.mesh_volume * 1e6, build.voxel_volume * 1e6,
                report.at("volume_error_percent").get<double>());
    std::printf("  distance to the raw surface: mean %.3f mm, max %.3f mm (%.2f voxels)\n", build.distance.mean * 1e3,
                build.distance.max * 1e3, report.at("hausdorff").at("max_voxels").get<double>());
    std::printf("  min angle %.1f deg, max aspect ratio %.1f\n", build.shape.min_angle_deg, build.shape.max_aspect);
    std::printf("  seconds: extract %.3f, smooth %.3f, to the budget %.3f (%s), total %.3f\n", s.at("extract").get<double>(),
                s.at("smooth").get<double>(), s.at("decimate").get<double>(), build.surface.decimator.c_str(),
                s.at("total").get<double>());
  }
}

void run_labels(const std::string& file) {
  const Volume v = read_volume(file);
  std::printf("%s\n  dims %zu x %zu x %zu, spacing %.4g x %.4g x %.4g mm, %zu layer(s)\n", file.c_str(), v.dims[0],
              v.dims[1], v.dims[2], v.spacing.x() * 1e3, v.spacing.y() * 1e3, v.spacing.z() * 1e3, v.layers.size());
  std::printf("  origin (LPS) %.2f %.2f %.2f mm\n", v.origin.x() * 1e3, v.origin.y() * 1e3, v.origin.z() * 1e3);
  for (int r = 0; r < 3; ++r)
    std::printf("  direction row %d: %.4f %.4f %.4f\n", r, v.direction(r, 0), v.direction(r, 1), v.direction(r, 2));
  for (std::size_t l = 0; l < v.layers.size(); ++l) {
    const std::map<int, std::size_t> counts = label_counts(v, static_cast<int>(l));
    if (counts.size() > 256) {
      std::printf("  layer %zu: %zu distinct values (a grey volume: use --threshold)\n", l, counts.size());
      continue;
    }
    for (const auto& [value, n] : counts) {
      const auto name = v.names.find({static_cast<int>(l), value});
      std::printf("  layer %zu label %4d  %9zu voxels  %10.2f cm3  %s\n", l, value, n,
                  static_cast<double>(n) * v.voxel_volume() * 1e6, name == v.names.end() ? "" : name->second.c_str());
    }
  }
}

void run_phantom(const PhantomArgs& a) {
  const Phantom p = make_phantom(a.name, a.voxel_mm * 1e-3);
  check_writable_dir(a.output);
  write_volume(p.volume, a.output);
  if (!a.class_map.empty()) {
    std::ofstream out(a.class_map);
    out << "# label value and name of " << a.name << " phantom (trocar mesh phantom)\n";
    for (const Phantom::Part& part : p.parts) out << part.label << " " << part.name << "\n";
    if (!out) throw FileError(a.class_map, FileLocation::none(), "cannot write the class map");
  }
  std::printf("phantom %s: %zu x %zu x %zu voxels of %.3g mm -> %s\n", a.name.c_str(), p.volume.dims[0],
              p.volume.dims[1], p.volume.dims[2], a.voxel_mm, a.output.c_str());
}

#else

[[noreturn]] void no_modelling() {
  throw Error("this trocar was built without the modelling module (install libvtk9-dev, libinsighttoolkit5-dev and "
              "libcgal-dev, e.g. with scripts/setup, and rebuild: docs/build.md)");
}

#endif

}  // namespace

void install_scene_mesh_builder() {
#if TROCAR_HAVE_MODELLING
  register_scene_mesh_builder();
#endif
}

void add_mesh_build_commands(CLI::App& mesh, int& exit_code) {
  (void)exit_code;
  auto a = std::make_shared<BuildArgs>();
  CLI::App* build = mesh.add_subcommand("build", "Build a closed, textured organ mesh from a labelled volume (NIfTI, NRRD, MetaImage)");
  build->add_option("volume", a->volume, "Label map or grey volume (.nii .nii.gz .nrrd .seg.nrrd .mha .mhd)")->required();
  build->add_option("-o,--output", a->output, "Organ mesh: .obj (+ .mtl + .png), .wrl (VRML97 + .png) or .stl")->required();
  build->add_option("--label", a->label, "Label value or segment name (names from the file or --class-map)");
  build->add_option("--threshold", a->threshold, "Grey range LOW [HIGH] instead of a label")->expected(1, 2);
  build->add_option("--class-map", a->class_map, "Label names: JSON {\"5\": \"liver\"} or lines \"5 liver\" (TotalSegmentator's map)");
  build->add_option("--layer", a->layer, "Layer of a multi-layer .seg.nrrd (default: the named segment's, else 0)");
  build->add_option("--target-triangles", a->target_triangles, "Triangle budget: remesh or decimate to at most this many (0: keep all)")->capture_default_str();
  build->add_option("--smooth-iterations", a->smooth_iterations, "Windowed-sinc smoothing iterations (0: none)")->check(CLI::Range(0, 1000))->capture_default_str();
  build->add_option("--passband", a->passband, "Windowed-sinc pass band (smaller: smoother)")->check(CLI::Range(1e-5, 2.0))->capture_default_str();
  build->add_option("--presmooth", a->presmooth_mm, "Gaussian pre-smoothing of the mask, sigma (mm; 0: none)")->check(CLI::NonNegativeNumber)->capture_default_str();
  build->add_option("--close", a->close_mm, "Morphological closing of the mask, ball radius (mm; 0: none): fills small tunnels and gaps")->check(CLI::NonNegativeNumber)->capture_default_str();
  build->add_flag("--all-components", a->all_components, "Keep every component of at least --min-component-voxels, not only the largest");
  build->add_option("--min-component-voxels", a->min_component_voxels, "Smallest component kept")->check(CLI::Range(std::size_t{1}, std::size_t{1} << 40))->capture_default_str();
  build->add_option("--stride", a->stride, "Extraction grid stride (0: auto, coarser only when the surface would far exceed the budget; 1: full resolution)")->check(CLI::Range(0, 8))->capture_default_str();
  build->add_option("--remesh", a->remesh, "Isotropic remeshing rounds to the budget (near-equilateral triangles); 0: edge-collapse decimation to exactly the budget")->check(CLI::Range(0, 50))->capture_default_str();
  build->add_option("--texture-size", a->texture_size, "Texels per atlas chart side (the PNG is 3x2 charts)")->check(CLI::Range(8, 4096))->capture_default_str();
  build->add_flag("--no-texture", a->no_texture, "No UVs and no texture");
  build->add_option("--report", a->report, "Write the build report (JSON)");
  build->add_flag("-q,--quiet", a->quiet, "No progress and no summary");

  auto labels_file = std::make_shared<std::string>();
  CLI::App* labels = mesh.add_subcommand("labels", "List a volume's geometry and its labels with voxel counts and names");
  labels->add_option("volume", *labels_file, "Volume file")->required();

  auto p = std::make_shared<PhantomArgs>();
  CLI::App* phantom = mesh.add_subcommand("phantom", "Write a labelled test volume made in code (sphere, ellipsoid, torus, touching-blobs, edge, abdomen)");
  phantom->add_option("name", p->name, "Phantom name")->required();
  phantom->add_option("-o,--output", p->output, "Volume file (.nii.gz .nii .nrrd .mha)")->required();
  phantom->add_option("--voxel", p->voxel_mm, "Voxel size (mm)")->check(CLI::Range(0.05, 20.0))->capture_default_str();
  phantom->add_option("--class-map", p->class_map, "Also write the label names to this file");

#if TROCAR_HAVE_MODELLING
  build->callback([a] { run_build(*a); });
  labels->callback([labels_file] { run_labels(*labels_file); });
  phantom->callback([p] { run_phantom(*p); });
#else
  // The callbacks hold the option targets alive (CLI11 writes into them while parsing).
  build->callback([a] { no_modelling(); });
  labels->callback([labels_file] { no_modelling(); });
  phantom->callback([p] { no_modelling(); });
#endif
}

}  // namespace trocar::cli

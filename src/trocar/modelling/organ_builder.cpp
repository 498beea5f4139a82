#include "trocar/modelling/organ_builder.h"

#include <chrono>
#include <cmath>

#include "trocar/core/error.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/repair.h"
#include "trocar/mesh/validate.h"
#include "trocar/modelling/organ_writers.h"

namespace trocar {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

Vec3 organ_colour(const std::string& organ) {
  const RgbImage swatch = organ_texture(organ, 8, 1e-3);
  Vec3 sum = Vec3::Zero();
  for (std::size_t p = 0; p < swatch.width * swatch.height; ++p) {
    for (int c = 0; c < 3; ++c) sum[c] += swatch.rgb[3 * p + static_cast<std::size_t>(c)];
  }
  return sum / (255.0 * static_cast<Real>(swatch.width * swatch.height));
}

OrganBuild build_organ(const Volume& volume, const OrganBuildOptions& options, const ProgressFn& progress) {
  OrganBuild b;
  b.mask = select_mask(volume, options.query);
  b.organ = !b.mask.name.empty() ? b.mask.name : b.mask.label != 0 ? "label " + std::to_string(b.mask.label) : "tissue";
  SurfaceOptions surface_options = options.surface;
  surface_options.reference_surface = surface_options.reference_surface && options.measure_distance;
  b.surface = extract_surface(volume, b.mask, surface_options, progress);
  b.mask.inside.clear();
  b.mask.inside.shrink_to_fit();
  b.mesh = std::move(b.surface.mesh);
  b.surface.mesh = TriMesh{};
  b.voxel_volume = static_cast<Real>(b.surface.kept_voxels) * volume.voxel_volume();
  b.mesh_volume = b.mesh.signed_volume();
  b.raw_volume = b.surface.raw.signed_volume();

  // The project's own checks: clean, and nothing for repair to do.
  auto t0 = Clock::now();
  const MeshReport report = validate(b.mesh);
  b.closed = report.closed;
  b.manifold = report.manifold;
  b.outward = report.orientation == Orientation::kOutward;
  b.defects = report.defects().size();
  TriMesh copy = b.mesh;
  b.repair_changes = repair(copy).summary().size();
  b.genus = genus(b.mesh);
  if (options.measure_distance && !b.surface.raw.empty()) b.distance = surface_distance(b.mesh, b.surface.raw);
  b.shape = shape_quality(b.mesh);
  b.seconds_quality = seconds_since(t0);
  if (!b.closed || !b.manifold || !b.outward || b.defects != 0 || b.repair_changes != 0) {
    std::string why;
    for (const std::string& d : report.defects()) why += (why.empty() ? "" : "; ") + d;
    throw Error(volume.source + ": " + b.mask.what + ": the built surface is not a clean closed outward manifold (" +
                (why.empty() ? "repair would change it" : why) + ")");
  }

  if (options.texture_chart_pixels > 0) {
    t0 = Clock::now();
    box_chart_uvs(b.mesh);
    b.seconds_uv = seconds_since(t0);
    t0 = Clock::now();
    b.texture = organ_texture(b.organ, options.texture_chart_pixels, atlas_texel_size(b.mesh, options.texture_chart_pixels));
    b.seconds_texture = seconds_since(t0);
  }
  if (progress) progress("checked", 1);
  return b;
}

nlohmann::json build_report(const OrganBuild& b, const Volume& volume) {
  using nlohmann::json;
  const Real voxel = volume.spacing.minCoeff();
  const auto& h = b.shape.aspect_histogram;
  json aspect = json::array();
  const char* bins[] = {"[1,1.5)", "[1.5,2)", "[2,3)", "[3,5)", "[5,10)", "[10,inf)"};
  for (std::size_t i = 0; i < h.size(); ++i) aspect.push_back({{"bin", bins[i]}, {"triangles", h[i]}});
  const SurfaceTimes& t = b.surface.times;
  const Aabb bounds = b.mesh.bounds();
  return json{
      {"input", volume.source},
      {"dims", {volume.dims[0], volume.dims[1], volume.dims[2]}},
      {"spacing_mm", {volume.spacing.x() * 1e3, volume.spacing.y() * 1e3, volume.spacing.z() * 1e3}},
      {"selection", b.mask.what},
      {"organ", b.organ},
      {"label_voxels", b.mask.count},
      {"kept_voxels", b.surface.kept_voxels},
      {"components", b.surface.components},
      {"components_kept", b.surface.components_kept},
      {"decimator", b.surface.decimator},
      {"extract_stride", b.surface.stride},
      {"thickness_voxels", b.surface.thickness_voxels},
      {"budget_edge_voxels", b.surface.edge_voxels},
      {"triangles", b.mesh.triangle_count()},
      {"vertices", b.mesh.vertex_count()},
      {"raw_triangles", b.surface.raw.triangle_count()},
      {"voxel_volume_cm3", b.voxel_volume * 1e6},
      {"mesh_volume_cm3", b.mesh_volume * 1e6},
      {"raw_volume_cm3", b.raw_volume * 1e6},
      {"volume_error_percent", 100 * (b.mesh_volume / b.voxel_volume - 1)},
      {"hausdorff", {{"mean_mm", b.distance.mean * 1e3}, {"max_mm", b.distance.max * 1e3},
                     {"mean_voxels", b.distance.mean / voxel}, {"max_voxels", b.distance.max / voxel},
                     {"against", "the full-resolution extracted surface; voxels of the smallest spacing"}}},
      {"bounds_m", {{"min", {bounds.min.x(), bounds.min.y(), bounds.min.z()}}, {"max", {bounds.max.x(), bounds.max.y(), bounds.max.z()}}}},
      {"world", "patient LPS, metres"},
      {"min_angle_deg", b.shape.min_angle_deg},
      {"mean_min_angle_deg", b.shape.mean_min_angle_deg},
      {"max_aspect_ratio", b.shape.max_aspect},
      {"aspect_ratio_histogram", aspect},
      {"genus", b.genus},
      {"closed", b.closed},
      {"manifold", b.manifold},
      {"outward", b.outward},
      {"defects", b.defects},
      {"repair_changes", b.repair_changes},
      {"uv", b.mesh.texcoords.empty() ? "none" : "box charts (6 projections by dominant normal axis, 3x2 atlas)"},
      {"seconds", {{"components", t.components}, {"extract", t.extract}, {"smooth", t.smooth},
                   {"decimate", t.decimate}, {"clean", t.clean}, {"checks", b.seconds_quality},
                   {"uv", b.seconds_uv}, {"texture", b.seconds_texture},
                   {"total", t.components + t.extract + t.smooth + t.decimate + t.clean + b.seconds_quality +
                                 b.seconds_uv + b.seconds_texture}}},
  };
}

void write_organ(const OrganBuild& b, const std::filesystem::path& path) {
  const std::string name = path.filename().string();
  const bool textured = !b.texture.rgb.empty() && !b.mesh.texcoords.empty();
  const std::filesystem::path png = std::filesystem::path(path).replace_extension(".png");
  const std::string png_name = textured ? png.filename().string() : "";
  if (ends_with(name, ".obj") || ends_with(name, ".OBJ")) {
    if (textured) write_png(b.texture, png);
    write_textured_obj(b.mesh, path, png_name, organ_colour(b.organ));
  } else if (ends_with(name, ".wrl") || ends_with(name, ".vrml")) {
    if (textured) write_png(b.texture, png);
    save_vrml(b.mesh, path, png_name, organ_colour(b.organ), b.organ);
  } else if (ends_with(name, ".stl")) {
    save_mesh(b.mesh, path);
  } else {
    throw FileError(path.string(), FileLocation::none(), "unknown output format (use .obj, .wrl or .stl)");
  }
}

}  // namespace trocar

#pragma once
/// The whole offline modelling pipeline: labelled volume → mask → closed, decimated, textured
/// organ mesh, checked by the project's own validate/repair, with a report of what it made.
#include <cstddef>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "trocar/mesh/tri_mesh.h"
#include "trocar/modelling/label_select.h"
#include "trocar/modelling/quality.h"
#include "trocar/modelling/surface.h"
#include "trocar/modelling/texture.h"
#include "trocar/modelling/volume.h"

namespace trocar {

/// Everything a build takes.
struct OrganBuildOptions {
  LabelQuery query;            ///< what to mesh
  SurfaceOptions surface;      ///< extraction, smoothing, decimation
  std::size_t texture_chart_pixels = 256;  ///< texels per atlas chart side (0: no UVs, no texture)
  bool measure_distance = true;            ///< Hausdorff distance to the raw surface (costs a locator)
};

/// What a build made, and its figures.
struct OrganBuild {
  TriMesh mesh;           ///< the organ (world, m), outward, box-chart UVs unless switched off
  RgbImage texture;       ///< the procedural texture (empty when switched off)
  Mask mask;              ///< the selection (counts and names); `inside` is released
  Surface surface;        ///< raw surface and stage times (surface.mesh is moved into `mesh`)
  std::string organ;      ///< the organ's name (segment name, else "label N")
  Real voxel_volume = 0;  ///< kept voxels × voxel volume (m³)
  Real mesh_volume = 0;   ///< enclosed volume of `mesh` (m³)
  Real raw_volume = 0;    ///< enclosed volume of the raw surface (m³)
  SurfaceDistance distance;   ///< `mesh` against the raw surface
  ShapeQuality shape;         ///< triangle angles and aspect ratios
  int genus = 0;              ///< total genus of `mesh`
  bool closed = false, manifold = false, outward = false;  ///< from validate()
  std::size_t defects = 0;            ///< defects validate() lists (0 expected)
  std::size_t repair_changes = 0;     ///< steps repair() would change (0 expected)
  double seconds_uv = 0, seconds_texture = 0, seconds_quality = 0;  ///< stage times
};

/// Runs the pipeline on a volume in memory. Throws FileError naming volume.source for an
/// unusable selection (see select_mask, extract_surface) and trocar::Error when the result is
/// not a closed manifold outward surface.
OrganBuild build_organ(const Volume& volume, const OrganBuildOptions& options, const ProgressFn& progress = {});

/// The report as JSON: input, selection, triangles, volumes, distances (mm and voxels of the
/// smallest spacing), angles, aspect histogram, genus, checks and stage times (s).
nlohmann::json build_report(const OrganBuild& build, const Volume& volume);

/// Writes the organ by the extension of `path`: .obj (+ .mtl and a .png texture of the same
/// stem), .wrl (VRML97 + .png), .stl (geometry only). Throws FileError.
void write_organ(const OrganBuild& build, const std::filesystem::path& path);

/// The organ's diffuse colour (the texture's mean tone), for MTL and VRML materials.
Vec3 organ_colour(const std::string& organ);

}  // namespace trocar

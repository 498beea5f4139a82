#pragma once
/// Texture coordinates and a procedural organ texture for a built organ.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// Box-chart UV atlas: each triangle goes to one of six charts by the dominant axis of its
/// normal (±x, ±y, ±z of the mesh's frame) and is projected orthographically onto that chart's
/// plane, at one scale for all charts (uniform texel density). The charts are laid out 3 × 2 in
/// the unit square, each with a gutter against filtering across charts.
///
/// Why this parameterisation: it works for any shape and genus (a torus, a concave liver,
/// where a spherical or cylindrical map folds over), a triangle is never flipped in UV, and the
/// stretch is bounded (the dominant normal component is ≥ 1/√3, so lengths grow by at most √3).
/// Seams lie where the dominant axis changes; triangles of one chart at different depths share
/// texels, which a procedural tissue texture hides. Per-corner coordinates (TriMesh::texcoords)
/// need no vertex splits at seams.
void box_chart_uvs(TriMesh& mesh);

/// An 8-bit RGB image, rows top to bottom.
struct RgbImage {
  std::size_t width = 0;          ///< pixels
  std::size_t height = 0;         ///< pixels
  std::vector<std::uint8_t> rgb;  ///< 3·width·height bytes
};

/// A procedural organ texture for the box-chart atlas: value-noise mottling, lobular patches
/// and darker vessel lines in the organ's colour (chosen from `organ`, e.g. "liver", "spleen",
/// "kidney", "gallbladder"; any other name gets a generic tissue colour). `texel_m` is the size
/// one texel covers on the organ, so features keep their size in millimetres. Deterministic.
RgbImage organ_texture(const std::string& organ, std::size_t chart_pixels, Real texel_m);

/// Texel size of the atlas box_chart_uvs() makes for `mesh` with charts of `chart_pixels`.
Real atlas_texel_size(const TriMesh& mesh, std::size_t chart_pixels);

/// Writes the image as PNG (VTK's writer). Throws FileError naming the file on failure.
void write_png(const RgbImage& image, const std::filesystem::path& path);

}  // namespace trocar

#pragma once
/// Choosing what to mesh in a volume: one label (by value or by name) or a grey-value range,
/// as a binary mask.
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "trocar/modelling/volume.h"

namespace trocar {

/// What to mesh. Exactly one of `label` and a threshold is set.
struct LabelQuery {
  /// A label value ("5") or a segment name ("liver"), matched against the names the file gives
  /// and then `class_map` (case-insensitive). Empty when thresholding.
  std::string label;
  std::optional<Real> threshold_low;   ///< inside when value ≥ this (grey volumes)
  std::optional<Real> threshold_high;  ///< inside when value ≤ this
  int layer = -1;                      ///< layer to read; -1: the named segment's, else 0
  std::map<int, std::string> class_map;  ///< names for label values the file does not name
};

/// A binary mask on the volume's grid.
struct Mask {
  std::vector<std::uint8_t> inside;  ///< 1 inside, 0 outside, same indexing as the volume
  std::size_t count = 0;             ///< voxels inside
  std::string what;                  ///< "label 5 (liver)" or "values in [200, inf]", for messages
  int label = 0;                     ///< the label value (0 when thresholding)
  std::string name;                  ///< the segment's name, when known
};

/// Voxels of `volume` the query selects. Throws FileError naming volume.source for an unknown
/// name, a label absent from the volume (listing those present), or an empty selection.
Mask select_mask(const Volume& volume, const LabelQuery& query);

/// The label values present in a layer (value ≠ 0) with their voxel counts.
std::map<int, std::size_t> label_counts(const Volume& volume, int layer = 0);

/// A class map file: a JSON object {"5": "liver", ...}, or lines "5 liver", "5: liver",
/// "5: 'liver'," (TotalSegmentator's map_to_binary.py dict body). Throws FileError naming the
/// line of anything else.
std::map<int, std::string> read_class_map(const std::filesystem::path& path);

}  // namespace trocar

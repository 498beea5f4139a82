#pragma once
// Pieces every command shares: the --method override of a scene and the atomic report write.
#include <filesystem>
#include <string>

#include "trocar/scene/scene.h"

namespace trocar::cli {

/// Sets the scene's response method from a --method value ("" keeps the scene's); throws
/// trocar::Error naming the known methods for an unknown one.
void apply_method_option(Scene& scene, const std::string& method);

/// Writes `text` to `path` through a temporary file in the same folder and a rename, so a reader
/// never sees half a report. Throws trocar::Error when the file cannot be written.
void write_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace trocar::cli

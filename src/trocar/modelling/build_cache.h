#pragma once
/// Scenes that name a volume instead of a mesh: `"mesh": {"build": "abdomen.nii.gz",
/// "label": "liver"}`. The organ is built once and cached by content hash (the volume's bytes,
/// the class map's and the options), so a second load reads the cached OBJ.
#include <filesystem>
#include <string>

#include "trocar/mesh/tri_mesh.h"
#include "trocar/scene/json_reader.h"

namespace trocar {

/// Where built organs are cached: $TROCAR_CACHE_DIR, else $XDG_CACHE_HOME/trocar, else
/// ~/.cache/trocar, else the temp directory's trocar-cache.
std::filesystem::path cache_dir();

/// The organ a scene's "mesh" object describes: keys build (volume path, relative to
/// scene_dir), label (value or name) or threshold [low, high], class_map (path), layer,
/// target_triangles, smooth_iterations, presmooth_mm, all_components, centre. Built and
/// cached, or read from the cache. Errors name the scene key and the reason.
TriMesh build_scene_mesh(const JsonReader& spec, const std::filesystem::path& scene_dir);

/// Installs build_scene_mesh as the scene loader's volume builder (scene/mesh_source.h).
void register_scene_mesh_builder();

}  // namespace trocar

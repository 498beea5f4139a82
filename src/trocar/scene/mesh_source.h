#pragma once
/// Where a scene object's mesh comes from: a file, or a procedural generator named in the scene
/// (`"mesh": {"generate": "icosphere", "radius": 0.03, "subdivisions": 3}`).
#include <filesystem>
#include <string>
#include <vector>

#include "trocar/mesh/tri_mesh.h"
#include "trocar/scene/json_reader.h"

namespace trocar {

/// One procedural kind: its scene name and the function building the mesh (metres) from the
/// "mesh" object (which it validates: every key, including "generate", must be known to it).
struct MeshGenerator {
  const char* name;                         ///< value of "generate"
  TriMesh (*make)(const JsonReader& spec);  ///< builds the mesh; errors through spec.fail()
  const char* summary;                      ///< keys and defaults, for docs and error messages
};

/// The table of generated kinds (the one registry: add a row in mesh_source.cpp for a new kind).
const std::vector<MeshGenerator>& mesh_generators();

/// Builds the mesh described by `spec` = {"generate": KIND, ...parameters}. Throws trocar::Error
/// naming the key path for an unknown kind or a bad parameter.
TriMesh make_generated_mesh(const JsonReader& spec);

/// Builds a mesh from an image volume a scene names (`"mesh": {"build": "liver.nii.gz", ...}`),
/// in metres. The optional modelling module (trocar::modelling, which the core does not link)
/// installs one; without it such a scene fails with a message saying so.
using VolumeMeshBuilder = TriMesh (*)(const JsonReader& spec, const std::filesystem::path& scene_dir);

/// Installs the volume builder (nullptr removes it). Call before loading scenes.
void set_volume_mesh_builder(VolumeMeshBuilder builder);

/// The "mesh" value of a scene object: a path string (relative to `scene_dir`; OBJ, STL, PLY,
/// VRML, VTK), a generator object, or a volume to build ({"build": ...}). Throws trocar::Error naming the key path when the file is
/// missing or unreadable.
TriMesh load_mesh_source(const JsonReader& mesh, const std::filesystem::path& scene_dir);

}  // namespace trocar

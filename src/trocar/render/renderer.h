#pragma once
/// The OpenGL 3.3 core renderer (docs/render.md). It draws a ViewSnapshot — never the live
/// Simulation — so it runs on its own thread at its own rate. Tissue normals are recomputed from
/// the deformed positions every frame; tissue gets a procedural solid texture (mottling, fat,
/// vessels) on its rest positions and the wet look of a headlight; instruments are steel. Needs a
/// current GL context (render/offscreen.h or a window) for its whole life.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "trocar/render/camera.h"
#include "trocar/sim/view_snapshot.h"
#include "trocar/sim/world.h"

namespace trocar {

/// What to draw besides the scene.
struct RenderOptions {
  bool contacts = true;       ///< contact points
  bool forces = true;         ///< force arrows at each instrument's contacts
  bool obb = false;           ///< each instrument's oriented bounding box
  bool cells = false;         ///< OHC cells holding both instrument and tissue vertices
  bool gauge = true;          ///< a force gauge (bar) per instrument, bottom left
  bool wireframe = false;     ///< tissue edges over the shading
  /// Flat colours and no overlays: tissue (255, 0, 0), instruments (0, 255, 0), rigids (0, 0, 255)
  /// on black; the tests compare this id pass with projected geometry.
  bool id_colors = false;
  Real vignette = 1.05;       ///< the scope's round image: darkening from this radius (half-heights); 0 = off
  Real force_scale = 0.01;    ///< arrow length per newton (m/N)
  Real gauge_max = 5;         ///< force at a full gauge (N)
  Real light_range = 0;       ///< headlight half-intensity distance (m); 0 = from the scene's size
};

/// Draws a World's snapshots.
class Renderer {
 public:
  /// Uploads the world's static geometry (instrument meshes, rigids, tissue topology). Throws
  /// trocar::Error when a shader does not compile (the driver's log in the message).
  /// `textures`: per tissue, a PNG mapped by the mesh's UVs (empty path: the procedural texture;
  /// Scene::textures). Throws trocar::Error naming an image that cannot be read.
  explicit Renderer(const World& world, const std::vector<std::filesystem::path>& textures = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Draws into the bound framebuffer's viewport (0, 0, width, height), clearing it first.
  void draw(const ViewSnapshot& snapshot, const CameraView& camera, const RenderOptions& options, int width,
            int height);

 private:
  struct Gpu;
  std::unique_ptr<Gpu> gpu_;
};

/// Area-weighted vertex normals of a triangle mesh (unit; zero for unused vertices).
void vertex_normals(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                    std::vector<float>& normals_xyz);

}  // namespace trocar

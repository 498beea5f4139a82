#pragma once
/// The OpenGL 3.3 core renderer (docs/render.md). It draws a ViewSnapshot — never the live
/// Simulation — so it runs on its own thread at its own rate. Tissue normals are recomputed from
/// the deformed positions every frame; tissue gets a procedural solid texture (mottling, fat,
/// vessels) on its rest positions and the wet look of a headlight; instruments are steel. What
/// electrosurgery and bleeding did is drawn too (docs/electrosurgery.md "What is drawn"): a cut
/// tissue's buffers follow its new model, burns and blood colour the triangles they touch, and
/// the blood's flow and the smoke run on the render side (effects_view.h). Needs a current GL
/// context (render/offscreen.h or a window) for its whole life.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "trocar/render/effects_view.h"
#include "trocar/scene/camera.h"
#include "trocar/scene/appearance.h"
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
  /// What electrosurgery and bleeding did (docs/electrosurgery.md "What is drawn"): burns, the
  /// blood's flow over the bleeding tissues, smoke. Off: tissue is drawn as if nothing had burnt
  /// or bled, and the blood and smoke wait (the blood is fed what it missed when turned back on).
  bool effects = true;
  bool smoke = true;          ///< the smoke (with effects)
  bool venting = false;       ///< a port's stopcock open: the smoke clears faster (SmokeField::set_venting)
};

/// How the scene's objects look (Scene::textures, tissue_appearance, rigid_appearance); a
/// missing entry or one not `given` keeps the renderer's default look.
struct SceneLook {
  std::vector<std::filesystem::path> textures;  ///< per tissue: a PNG mapped by its UVs (empty: procedural)
  std::vector<Appearance> tissues;              ///< per tissue
  std::vector<Appearance> rigids;               ///< per rigid
};

/// Draws a World's snapshots.
class Renderer {
 public:
  /// Uploads the world's static geometry (instrument meshes, rigids, tissue topology, the tack).
  /// Throws trocar::Error when a shader does not compile (the driver's log in the message), or
  /// naming a texture image that cannot be read. A texture is used where its appearance's
  /// pattern is the default.
  Renderer(const World& world, const SceneLook& look);
  /// The same with textures only (Scene::textures) and default appearances.
  explicit Renderer(const World& world, const std::vector<std::filesystem::path>& textures = {})
      : Renderer(world, SceneLook{textures, {}, {}}) {}
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Draws into the bound framebuffer's viewport (0, 0, width, height), clearing it first:
  /// opaque objects, then the tacks, then translucent objects (opacity < 1) far to near with
  /// depth writes off, then the smoke, then the overlays.
  ///
  /// A tissue whose model changed (a cut: snapshot.tissue_versions moved) has its buffers rebuilt
  /// from snapshot.tissue_triangles and tissue_rest first. Before drawing, the blood and smoke are
  /// brought up to the snapshot's time (effects()): consecutive snapshots are a run's frames; a
  /// snapshot earlier than the last one starts them afresh. Drawing the same snapshot again
  /// changes nothing.
  void draw(const ViewSnapshot& snapshot, const CameraView& camera, const RenderOptions& options, int width,
            int height);

  /// The blood and smoke kept between frames (read-only: for tests and statistics).
  const EffectsView& effects() const;

 private:
  struct Gpu;
  std::unique_ptr<Gpu> gpu_;
};

/// The helical tack as drawn, in its own frame: a titanium coil 4 mm long and 4 mm across about
/// +z, its flat head turn and cross-bar at z = +0.5 mm (above the surface) and the coil sinking to
/// z = −3.5 mm; the origin is where it enters the surface. Closed tubes, metres.
TriMesh make_tack_mesh();

/// Area-weighted vertex normals of a triangle mesh (unit; zero for unused vertices).
void vertex_normals(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                    std::vector<float>& normals_xyz);

}  // namespace trocar

#pragma once
/// How an object looks (scene key "appearance" of a tissue or rigid, or set by a generated
/// anatomy): its colour, opacity and surface pattern. Plain data for the renderer.
#include <array>

namespace trocar {

/// The pattern drawn on a surface.
enum class SurfacePattern {
  kDefault,  ///< the renderer's own (the procedural tissue texture, or the mesh's texture image)
  kPlain,    ///< the colour alone, with light
  kWeave,    ///< an open knitted weave with holes (the prosthetic mesh): transparent between threads
};

/// One object's look. `given` is false when the scene says nothing (the renderer's defaults).
struct Appearance {
  bool given = false;
  std::array<float, 3> colour{0.85f, 0.45f, 0.45f};  ///< linear RGB in [0, 1]
  float opacity = 1.0f;                              ///< 1 opaque, 0 invisible
  SurfacePattern pattern = SurfacePattern::kDefault;
};

}  // namespace trocar

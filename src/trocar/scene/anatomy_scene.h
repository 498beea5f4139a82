#pragma once
/// The scene keys of a generated anatomy (docs/anatomy.md, docs/scene.md): the top-level
/// "anatomy" object, expanded into tissues, rigids, zones, landmarks and appearances, and the
/// per-object "appearance" of a tissue or rigid.
#include "trocar/scene/appearance.h"
#include "trocar/scene/json_reader.h"
#include "trocar/scene/scene.h"

namespace trocar {

/// "anatomy": {"generate": "tapp-inguinal", "hernia": "indirect" | "direct", and optional
/// "cell", "tube_segments", "tube_spacing", "sac_segments", "sac_rings", "defect_diameter",
/// "sac_length", "sac_k_home"}. Appends its tissues (renumbered for locality, as read_tissue
/// does) and rigids to the scene's world, with their appearances, zones and landmarks.
void read_anatomy(const JsonReader& spec, Scene& scene);

/// "appearance": {"colour": [r, g, b] in [0, 1], "opacity": o in [0, 1], "pattern": "default" |
/// "plain" | "weave"}; every key optional.
Appearance read_appearance(const JsonReader& spec);

}  // namespace trocar

// Placeholder: material presets land here. Replace this whole file.
#include "trocar/tissue/material.h"

#include "trocar/core/error.h"

namespace trocar {

MassSpringMaterial material_preset(const std::string& name) { throw Error("unknown material preset '" + name + "'"); }
std::vector<std::string> material_preset_names() { return {}; }

}  // namespace trocar

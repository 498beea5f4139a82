#pragma once
/// The scene's "events": scripted actions (procedure/actions.h) by instrument name.
#include <vector>

#include "trocar/procedure/actions.h"
#include "trocar/scene/json_reader.h"
#include "trocar/sim/world.h"

namespace trocar {

/// Reads "events": [{"t": s, "action": "fire" | "exchange", "instrument": name}, ...]. The
/// instruments must be read already. Throws trocar::Error naming the key on a bad entry.
std::vector<ScriptedAction> read_actions(const JsonReader& list, const World& world);

}  // namespace trocar

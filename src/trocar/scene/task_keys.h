#pragma once
/// Scene keys of the procedure (docs/scene.md, docs/procedure.md): "zones" (named regions added to
/// the anatomy's), "landmarks" (named points, overriding the anatomy's) and "task" (the TaskSpec,
/// its tissue names and landmarks checked against the scene).
#include "trocar/scene/json_reader.h"
#include "trocar/scene/scene.h"

namespace trocar {

/// Reads the root's "zones", "landmarks" and "task" into the scene. Call after the tissues (and
/// anything else that adds zones or landmarks) are read: the task's names are checked against
/// them, and an unknown one fails naming its key.
void read_task_keys(const JsonReader& root, Scene& scene);

}  // namespace trocar

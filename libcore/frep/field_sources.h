// Node types whose field is read from a file: `mesh_sdf` (a closed triangle mesh's signed
// distance) and `vdb_grid` (an OpenVDB grid). The registry declares them here, with their
// parameters and docs, so the model format, `frepcad info` and the node reference know them;
// the layer that can read such files (volume/, with OpenVDB and CGAL) provides the loader at
// start-up (volume/field_sources.h: registerVolumeSources). frep/ itself knows neither
// library. A program built without that layer refuses these nodes with a message.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "frep/field.h"
#include "frep/tree.h"

namespace frep {

// Makes the field of a node of the type the loader is set for; throws ModelError or
// FileError naming the file and what is wrong. Called at compile time (and for structural
// bounds), so a loader caches what it reads.
using FieldSourceLoader = std::function<std::shared_ptr<const Field>(const Node& node)>;

void setFieldSourceLoader(const std::string& typeId, FieldSourceLoader loader);
std::shared_ptr<const Field> loadFieldSource(const Node& node);

}  // namespace frep

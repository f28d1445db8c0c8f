// The FRepCAD model file: a JSON document holding a tree and its export settings.
// Format reference: docs/file-formats.md. Every value is validated against the registry;
// errors name the file, the node's path, the parameter and what is allowed.
#pragma once

#include <optional>
#include <string>

#include "frep/tree.h"
#include "frep/vec.h"

namespace frep {

struct Model {
  NodePtr root;
  std::optional<Box3> bbox;          // export bounding box
  std::optional<double> resolution;  // export cell size
  std::string description;
};

// Parses a model from JSON text; `source` names it in error messages. Throws ModelError.
Model parseModel(const std::string& text, const std::string& source = "model");
// Reads and parses a model file. Throws FileError (unreadable) or ModelError.
Model loadModel(const std::string& path);
// Serialises a model (shared nodes are written once under "definitions").
std::string modelToJson(const Model& model);

}  // namespace frep

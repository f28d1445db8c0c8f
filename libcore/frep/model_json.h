// The FRepCAD model file: a JSON document holding a tree and its export settings.
// Format reference: docs/file-formats.md. Every value is validated against the registry;
// errors name the file, the node's path, the parameter and what is allowed.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "base/vec.h"
#include "frep/tree.h"

namespace frep {

// The "frepcad" version this build reads and writes.
constexpr int kModelFormatVersion = 1;
// A model file larger than this is refused before it is read (a hostile or mistaken file).
constexpr std::uint64_t kMaxModelBytes = 64ull << 20;

struct Model {
  NodePtr root;
  std::optional<Box3> bbox;          // export bounding box
  std::optional<double> resolution;  // export cell size
  std::string description;
  // Names for the nodes' features where the source had them (HyperFun's variable names);
  // not written to JSON.
  std::map<const Node*, std::string> labels;
  // The box to mesh when the solid's own extent cannot be found (a HyperFun program: its
  // polygonizer's -10..10); the export says when it uses it.
  std::optional<Box3> fallbackBox;
};

// Parses a model from JSON text; `source` names it in error messages. Relative file paths
// (mesh_sdf, vdb_grid) are taken from `baseDirectory` when it is given. Throws ModelError.
Model parseModel(const std::string& text, const std::string& source = "model",
                 const std::string& baseDirectory = "");
// Reads and parses a model file (relative file paths in it: from its folder). Throws FileError
// (unreadable) or ModelError.
Model loadModel(const std::string& path);
// Serialises a model (shared nodes are written once under "definitions").
std::string modelToJson(const Model& model);

}  // namespace frep

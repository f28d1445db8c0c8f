// Renders the registry for people and programs: `frepcad info` text and JSON, and the node
// reference page in docs/ (generated, never written by hand).
#pragma once

#include <string>

#include "frep/registry.h"

namespace frep {

std::string nodeTypeText(const NodeType& t);
std::string nodeTypeJson(const NodeType& t);  // one JSON object
std::string registryJson();                   // JSON array of every type
std::string registryMarkdown();               // docs/node-reference.md

}  // namespace frep

#include <iostream>
#include <nlohmann/json.hpp>

#include "base/file_names.h"
#include "cli/commands.h"
#include "cli/heavy_module.h"
#include "frep/registry_docs.h"

namespace frep::cli {

int infoCommand(const Args& args) {
  std::string type;
  bool json = false, markdown = false;
  for (const auto& a : args) {
    if (a == "-h" || a == "--help") {
      std::cout << "usage: frepcad info [TYPE] [--json | --markdown]\n"
                   "       frepcad info FILE.vdb [--json]\n\n"
                   "Lists the node types of the model format with their parameters (one type\n"
                   "with TYPE), as text, JSON or the Markdown of docs/node-reference.md; or the\n"
                   "grids of an OpenVDB file (names, value types, classes, voxel sizes, counts).\n";
      return 0;
    }
    if (a == "--json")
      json = true;
    else if (a == "--markdown")
      markdown = true;
    else if (!a.empty() && a[0] == '-')
      throw UsageError("unknown option '" + a + "' for info");
    else if (!type.empty())
      throw UsageError("info takes one node type or .vdb file; got '" + type + "' and '" + a + "'");
    else
      type = a;
  }
  if (isVdbPath(type)) {
    if (markdown) throw UsageError("--markdown lists node types, not a .vdb file's grids");
    return heavyModule().vdbInfo(type, json);
  }
  if (markdown) {
    std::cout << registryMarkdown();
    return 0;
  }
  if (!type.empty()) {
    const NodeType& t = registry().get(type);  // ModelError lists the known types
    std::cout << (json ? nodeTypeJson(t) : nodeTypeText(t));
    return 0;
  }
  if (json) {
    std::cout << registryJson();
    return 0;
  }
  for (const NodeType* t : registry().all()) std::cout << nodeTypeText(*t) << "\n";
  return 0;
}

}  // namespace frep::cli

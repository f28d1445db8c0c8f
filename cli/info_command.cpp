#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "frep/registry_docs.h"
#include "volume/grid_set.h"

namespace frep::cli {

namespace {

// `frepcad info FILE.vdb`: the file's grids, to pick one for a vdb_grid node.
int vdbInfo(const std::string& path, bool json) {
  const GridSet grids = readVdb(path);
  if (!json) {
    std::cout << path << ": " << grids.size() << " grid" << (grids.size() == 1 ? "" : "s") << "\n";
    for (std::size_t i = 0; i < grids.size(); ++i) {
      const GridInfo g = grids.info(i);
      std::cout << "  " << describeGrid(g) << "\n";
      if (g.worldBox.lo[0] <= g.worldBox.hi[0])
        std::cout << "    box [" << g.worldBox.lo[0] << ", " << g.worldBox.lo[1] << ", "
                  << g.worldBox.lo[2] << "] - [" << g.worldBox.hi[0] << ", " << g.worldBox.hi[1]
                  << ", " << g.worldBox.hi[2] << "]\n";
    }
    return 0;
  }
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t i = 0; i < grids.size(); ++i) {
    const GridInfo g = grids.info(i);
    out.push_back({{"name", g.name},
                   {"value_type", g.valueType},
                   {"grid_class", g.gridClass},
                   {"voxel_size", {g.voxelSize[0], g.voxelSize[1], g.voxelSize[2]}},
                   {"active_voxels", g.activeVoxels},
                   {"metadata", g.metadata}});
  }
  std::cout << out.dump(2) << "\n";
  return 0;
}

}  // namespace

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
    if (a == "--json") json = true;
    else if (a == "--markdown") markdown = true;
    else if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + a + "' for info");
    else type = a;
  }
  if (isVdbPath(type)) {
    if (markdown) throw UsageError("--markdown lists node types, not a .vdb file's grids");
    return vdbInfo(type, json);
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

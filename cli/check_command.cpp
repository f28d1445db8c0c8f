#include <iostream>

#include "check/mesh_check.h"
#include "cli/commands.h"
#include "mesh/mesh_io.h"

namespace frep::cli {

int checkCommand(const Args& args) {
  std::string path;
  bool json = false;
  for (const auto& a : args) {
    if (a == "--json") json = true;
    else if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + a + "' for check");
    else if (path.empty()) path = a;
    else throw UsageError("check takes one mesh file, got a second: '" + a + "'");
  }
  if (path.empty()) throw UsageError("check needs a mesh file (.stl, .obj or .ply)");
  const CheckReport report = checkMesh(readMesh(path));
  std::cout << (json ? reportToJson(report, path) : reportToText(report, path));
  return report.printable() ? 0 : 1;
}

}  // namespace frep::cli

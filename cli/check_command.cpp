#include <iostream>

#include "check/mesh_check.h"
#include "cli/commands.h"
#include "io/mesh_io.h"

namespace frep::cli {

int checkCommand(const Args& args) {
  std::string path;
  bool json = false;
  for (const auto& a : args) {
    if (a == "-h" || a == "--help") {
      std::cout << "usage: frepcad check MESH [--json]\n\n"
                   "Judges a mesh file (STL, OBJ, PLY) with CGAL: closed, manifold, outward,\n"
                   "free of self-intersections and degenerate triangles.\n"
                   "exit status: 0 printable, 1 not printable, 2 bad input\n";
      return 0;
    }
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

#include <cmath>
#include <iostream>
#include <sstream>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "check/printability.h"
#include "cli/commands.h"
#include "cli/terminal_progress.h"
#include "io/mesh_io.h"

namespace frep::cli {

namespace {

const char* const kCheckHelp =
    "usage: frepcad check MESH [--json] [--print [--min-wall MM] [--material NAME |\n"
    "                     --density G_CM3] [--up x|y|z|-x|-y|-z] [--overhang DEG]]\n\n"
    "Judges a mesh file (STL, OBJ, PLY, 3MF) with CGAL: closed, manifold, outward,\n"
    "free of self-intersections and degenerate triangles.\n"
    "  --print            also what a printer makes of it: the thinnest wall (rays cast\n"
    "                     into the solid from every triangle), the overhang area for the\n"
    "                     build direction, height, volume, area and mass\n"
    "  --min-wall MM      count the triangles where the wall is thinner than MM; the\n"
    "                     mesh is then not printable when any is\n"
    "  --material NAME    the density for the mass: pla, petg, abs, asa, nylon, tpu,\n"
    "                     resin, 316l, ti64, alsi10mg\n"
    "  --density D        the density in g/cm3 (units taken as mm)\n"
    "  --up AXIS          the build direction (default z)\n"
    "  --overhang DEG     a downward face steeper than DEG from vertical needs support\n"
    "                     (default 45)\n"
    "exit status: 0 printable, 1 not printable, 2 bad input\n";

Vec3 parseAxis(const std::string& s) {
  static const struct {
    const char* name;
    Vec3 v;
  } axes[] = {{"x", {1, 0, 0}},   {"y", {0, 1, 0}},   {"z", {0, 0, 1}},
              {"-x", {-1, 0, 0}}, {"-y", {0, -1, 0}}, {"-z", {0, 0, -1}}};
  for (const auto& a : axes)
    if (s == a.name) return a.v;
  throw UsageError("--up must be one of x, y, z, -x, -y, -z, got '" + s + "'");
}

}  // namespace

int checkCommand(const Args& args) {
  std::string path;
  bool json = false, print = false, printOption = false;
  PrintabilityOptions po;
  std::string densityFrom;  // the option that gave the density: a second one contradicts it
  auto densityOnce = [&](const std::string& given) {
    if (!densityFrom.empty())
      throw UsageError(densityFrom + " and " + given + " both give the density; give one");
    densityFrom = given;
  };
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
      printOption = true;
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      std::cout << kCheckHelp;
      return 0;
    }
    if (a == "--json")
      json = true;
    else if (a == "--print")
      print = true;
    else if (a == "--min-wall") {
      po.minWall = parseNumber(value(), a);
      if (!(*po.minWall > 0) || !std::isfinite(*po.minWall))
        throw UsageError("--min-wall must be a thickness > 0 (mm), got '" + args[i] + "'");
    } else if (a == "--material") {
      const std::string& name = value();
      densityOnce(a + " " + name);
      try {
        po.density = materialDensity(name);
      } catch (const ModelError& e) {
        throw UsageError(std::string("--material: ") + e.what());
      }
    } else if (a == "--density") {
      const std::string& density = value();
      densityOnce(a + " " + density);
      po.density = parseNumber(density, a);
      if (!(po.density > 0) || !std::isfinite(po.density))
        throw UsageError("--density must be > 0 (g/cm3), got '" + args[i] + "'");
    } else if (a == "--up")
      po.up = parseAxis(value());
    else if (a == "--overhang") {
      po.overhangDeg = parseNumber(value(), a);
      if (!(po.overhangDeg >= 0 && po.overhangDeg <= 90))
        throw UsageError("--overhang must be an angle from 0 to 90 degrees, got '" + args[i] + "'");
    } else if (!a.empty() && a[0] == '-')
      throw UsageError("unknown option '" + a + "' for check");
    else if (path.empty())
      path = a;
    else
      throw UsageError("check takes one mesh file, got a second: '" + a + "'");
  }
  if (path.empty()) throw UsageError("check needs a mesh file (.stl, .obj, .ply, .off or .3mf)");
  if (printOption && !print)
    throw UsageError("--min-wall, --material, --density, --up and --overhang apply with --print");
  // Ctrl-C is looked at while the file is read and between the check's passes.
  installInterruptHandlers();
  const TriangleMesh mesh = readMesh(path, ProgressCallback([](double) { return !interrupted(); }));
  CheckReport report = checkMesh(mesh, [](double) {
    if (interrupted()) throw Cancelled();
  });
  if (!print) {
    std::cout << (json ? reportToJson(report, path) : reportToText(report, path));
    return report.printable() ? 0 : 1;
  }
  po.thickness = report.printable();
  const PrintabilityReport p = measurePrintability(mesh, po);
  if (interrupted()) throw Cancelled();
  addPrintabilityReasons(report, p, po);
  if (json)
    std::cout << printabilityToJson(report, p, po, path);
  else
    std::cout << reportToText(report, path) << printabilityToText(p, po);
  return report.printable() ? 0 : 1;
}

}  // namespace frep::cli

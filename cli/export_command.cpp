#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "check/mesh_check.h"
#include "cli/commands.h"
#include "frep/bounds.h"
#include "frep/errors.h"
#include "frep/model_json.h"
#include "frep/structural_bounds.h"
#include "mesh/mesh_io.h"
#include "mesh/mesher.h"

namespace frep::cli {

namespace {
// The solid's own box, found by interval arithmetic, padded by 1.5 cells (at the given cell
// size, or the default 1/128 of the box) so the surface never touches the meshing box.
Box3 automaticBox(const std::string& modelPath, const Model& model, const Program& program,
                  double& resolution) {
  BoundsOptions o;
  o.known = structuralBounds(model.root);
  const SolidBounds b = findBounds(program, o);
  if (b.empty) throw ModelError(modelPath + ": the solid is empty: no point is inside");
  if (!b.bounded())
    throw ModelError(modelPath + ": the solid is unbounded; give --bbox x0 y0 z0 x1 y1 z1, set "
                                 "export.bbox in the model or intersect it with a bounded solid");
  double longest = 1e-9;
  for (int a = 0; a < 3; ++a) longest = std::max(longest, b.box.hi[a] - b.box.lo[a]);
  if (!(resolution > 0.0)) resolution = longest / 128.0;
  const double pad = 1.5 * resolution + 1e-3 * longest;
  Box3 box = b.box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] -= pad;
    box.hi[a] += pad;
  }
  return box;
}
}  // namespace

int exportCommand(const Args& args) {
  for (const std::string& a : args)
    if (isDocumentPath(a)) return exportDocument(args);
  std::string modelPath, outPath, formatText;
  std::optional<double> resolution;
  std::optional<Box3> bbox;
  bool force = false, quiet = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](const char* what) -> const std::string& {
      if (i + 1 >= args.size()) throw UsageError(a + " expects " + what);
      return args[++i];
    };
    if (a == "-o" || a == "--output") outPath = value("an output file");
    else if (a == "--resolution") resolution = parseNumber(value("a cell size"), a);
    else if (a == "--format") formatText = value("a format");
    else if (a == "--force") force = true;
    else if (a == "--quiet") quiet = true;
    else if (a == "--bbox") {
      Box3 b;
      for (int k = 0; k < 6; ++k) {
        const double v = parseNumber(value("6 numbers x0 y0 z0 x1 y1 z1"), a);
        (k < 3 ? b.lo[k] : b.hi[k - 3]) = v;
      }
      if (!b.valid()) throw UsageError("--bbox needs x0 < x1, y0 < y1, z0 < z1");
      bbox = b;
    } else if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + a + "' for export");
    else if (modelPath.empty()) modelPath = a;
    else throw UsageError("export takes one model file, got a second: '" + a + "'");
  }
  if (modelPath.empty()) throw UsageError("export needs a model file");
  if (outPath.empty()) throw UsageError("export needs -o OUT");
  const MeshFormat format = formatText.empty() ? formatFromPath(outPath) : parseFormat(formatText);
  if (resolution && !(*resolution > 0)) throw UsageError("--resolution must be > 0");

  const Model model = loadModel(modelPath);
  const Program program = compile(model.root);
  if (!bbox) bbox = model.bbox;
  if (!resolution) resolution = model.resolution;
  if (!bbox) {
    if (!resolution) resolution = 0.0;  // 0: 1/128 of the solid's box, set by automaticBox
    bbox = automaticBox(modelPath, model, program, *resolution);
  }
  if (!resolution) {
    const double extent = std::max({bbox->hi[0] - bbox->lo[0], bbox->hi[1] - bbox->lo[1],
                                    bbox->hi[2] - bbox->lo[2]});
    resolution = extent / 128.0;
  }

  MeshingOptions options;
  options.bbox = *bbox;
  options.resolution = *resolution;
  const bool showProgress = !quiet && isatty(STDERR_FILENO);
  if (showProgress)
    options.progress = [](double f) {
      std::fprintf(stderr, "\rmeshing %3d%%", static_cast<int>(f * 100));
      return true;
    };
  MeshingStats stats;
  const TriangleMesh mesh = polygonize(program, options, &stats);
  if (showProgress) std::fprintf(stderr, "\r              \r");
  if (!quiet)
    std::cout << "meshed " << modelPath << ": " << mesh.triangleCount() << " triangles, grid "
              << stats.cells[0] << "x" << stats.cells[1] << "x" << stats.cells[2] << ", "
              << stats.seconds << " s\n";

  const CheckReport report = checkMesh(mesh);
  if (!quiet || !report.printable()) std::cout << reportToText(report, outPath);
  if (!report.printable() && !force) {
    std::cerr << "frepcad: refusing to write " << outPath
              << ": the mesh is not printable (see reasons above; --force writes it anyway)\n";
    return 1;
  }
  writeMesh(mesh, outPath, format);
  if (!quiet) std::cout << "wrote " << outPath << " (" << formatName(format) << ")\n";
  return report.printable() ? 0 : 1;
}

}  // namespace frep::cli

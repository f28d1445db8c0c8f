#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "check/mesh_check.h"
#include "cli/commands.h"
#include "frep/errors.h"
#include "frep/model_json.h"
#include "mesh/mesh_io.h"
#include "mesh/mesher.h"

namespace frep::cli {

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
  if (!bbox) bbox = model.bbox;
  if (!bbox)
    throw ModelError(modelPath + ": no bounding box: give --bbox x0 y0 z0 x1 y1 z1 or set "
                                 "export.bbox in the model");
  if (!resolution) resolution = model.resolution;
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
  const Program program = compile(model.root);
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

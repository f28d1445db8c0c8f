// frepcad repair: any mesh file made printable (libcore/repair), judged by the check before
// and after, written atomically only when it passes (or with --force); the input is only read.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "base/errors.h"
#include "base/file_names.h"
#include "check/mesh_deviation.h"
#include "cli/commands.h"
#include "cli/terminal_progress.h"
#include "io/mesh_3mf.h"
#include "io/mesh_io.h"
#include "pipeline/export_pipeline.h"
#include "repair/repair.h"

namespace frep::cli {

namespace {

const char* const kRepairHelp =
    "usage: frepcad repair IN -o OUT [--rebuild auto|never|always] [--voxel V] [--weld D]\n"
    "                      [--no-fill] [--max-deviation D] [--allow-pieces] [--format F]\n"
    "                      [--units U] [--force] [--json] [--quiet]\n\n"
    "Makes a mesh (STL, OBJ, PLY, 3MF) printable: welds near-duplicate vertices, removes\n"
    "degenerate and duplicate triangles, stitches coincident borders, fills holes, splits\n"
    "non-manifold vertices, removes self-intersections and orients every shell outward\n"
    "(CGAL). When that is not enough (intersecting shells, crossings CGAL cannot undo\n"
    "locally) it rebuilds the solid through an OpenVDB level set meshed by FRepCAD's own\n"
    "mesher, printable by construction. The result is checked and judged against IN: no\n"
    "more pieces than IN has, no surface farther than the bound from IN's, no part of IN\n"
    "lost farther than it (an open sheet closed by a far cap fails this). IN is never\n"
    "changed.\n"
    "  -o, --output OUT   the repaired mesh (.stl, .obj, .ply, .3mf, .bms)\n"
    "  --rebuild P        auto: only when the local repairs are not enough (default);\n"
    "                     never: local repairs only; always: rebuild whatever the result\n"
    "  --voxel V          the rebuild's voxel size (default: the longest side / 192)\n"
    "  --weld D           weld vertices closer than D (default: a hundredth of the median\n"
    "                     edge length, widened to a tenth while that closes cracks; 0:\n"
    "                     identical coordinates only)\n"
    "  --no-fill          leave holes open (the result then stays unprintable)\n"
    "  --max-deviation D  the bound on how far the result and IN may lie apart (default:\n"
    "                     2 % of IN's diagonal); raise it to accept a cap the report names\n"
    "  --allow-pieces     accept a result of more pieces than IN has\n"
    "  --format F         stl, stl-ascii, obj, ply, bms or 3mf (default: from OUT)\n"
    "  --units U          a 3MF's unit: micron, mm, cm, inch, ft, m (default mm)\n"
    "  --force            write the result even when it is still not printable\n"
    "  --json             the report as JSON on standard output\n"
    "exit status: 0 repaired and written, 1 still not printable or not faithful to IN (the\n"
    "reasons and figures are printed; nothing written without --force), 2 bad input (a\n"
    "rebuild too large for the memory there is names the voxel that fits), 130 cancelled\n";

std::string dumped(const nlohmann::json& j) {
  // file names are bytes: invalid UTF-8 is replaced rather than failing the report
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace

int repairCommand(const Args& args) {
  std::string input, output, format, units;
  RepairOptions options;
  bool force = false, json = false, quiet = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      std::cout << kRepairHelp;
      return 0;
    } else if (a == "-o" || a == "--output")
      output = value();
    else if (a == "--rebuild")
      options.rebuild = parseRebuildPolicy(value());
    else if (a == "--voxel") {
      options.voxel = parseNumber(value(), a);
      if (!(options.voxel > 0) || !std::isfinite(options.voxel))
        throw UsageError("--voxel must be a size > 0, got '" + args[i] + "'");
    } else if (a == "--weld") {
      options.weldDistance = parseNumber(value(), a);
      if (!(options.weldDistance >= 0) || !std::isfinite(options.weldDistance))
        throw UsageError("--weld must be a distance >= 0, got '" + args[i] + "'");
    } else if (a == "--max-deviation") {
      options.maxDeviation = parseNumber(value(), a);
      if (!(options.maxDeviation > 0) || !std::isfinite(options.maxDeviation))
        throw UsageError("--max-deviation must be a distance > 0, got '" + args[i] + "'");
    } else if (a == "--allow-pieces")
      options.allowMorePieces = true;
    else if (a == "--no-fill")
      options.fillHoles = false;
    else if (a == "--format")
      format = value();
    else if (a == "--units")
      units = value();
    else if (a == "--force")
      force = true;
    else if (a == "--json")
      json = true;
    else if (a == "--quiet")
      quiet = true;
    else if (!a.empty() && a[0] == '-' && a.size() > 1)
      throw UsageError("unknown option '" + a + "' for repair (see frepcad repair --help)");
    else if (input.empty())
      input = a;
    else
      throw UsageError("repair takes one input mesh, got a second: '" + a + "'");
  }
  if (input.empty())
    throw UsageError("repair needs an input mesh (.stl, .obj, .ply, .off or .3mf)");
  if (output.empty()) throw UsageError("repair needs -o OUT");
  const MeshFormat outFormat = format.empty() ? formatFromPath(output) : parseFormat(format);
  ThreeMfOptions threeMf;
  if (!units.empty()) {
    if (outFormat != MeshFormat::ThreeMf) throw UsageError("--units applies to a .3mf output only");
    threeMf.unit = parseLengthUnit(units);
  }
  checkOutputPath(output, input);
  const TriangleMesh mesh = readMesh(input);

  installInterruptHandlers();
  options.progress = [](double) { return !interrupted(); };
  const RepairResult r = repairMesh(mesh, options, displayName(input));
  if (interrupted()) throw Cancelled();

  // The verdict on what is written: a 3MF holds its coordinates rounded (io/mesh_3mf.h), so
  // its package is checked as read back, like every 3MF export (pipeline's export3mf).
  CheckReport verdict = r.after;
  bool written = false;
  if ((r.accepted() || force) && !r.mesh.triangles.empty()) {
    if (outFormat == MeshFormat::ThreeMf) {
      threeMf.metadata = {{"Application", "FRepCAD frepcad repair"}};
      const ThreeMfExportResult e =
          export3mf({{std::filesystem::path(output).stem().string(), r.mesh}}, threeMf, output,
                    force, [](double) { return !interrupted(); });
      verdict = e.reports.at(0);
      written = e.written;
    } else {
      writeMesh(r.mesh, output, outFormat, [](double) { return !interrupted(); });
      written = true;
    }
  }

  if (json) {
    nlohmann::json j;
    j["input"] = displayName(input);
    j["output"] = displayName(output);
    j["printable_before"] = r.before.printable();
    j["printable"] = verdict.printable();
    j["accepted"] = verdict.printable() && r.departures.empty();
    j["written"] = written;
    j["rebuilt"] = r.rebuilt;
    j["voxel"] = r.voxel;
    j["triangles_before"] = r.before.faces;
    j["triangles"] = r.mesh.triangles.size();
    j["deviation"] = r.deviation.hausdorff();
    // (deviation is the input's a, the result b) the result's surface to the input's, and
    // the input's to the result's where it lies outside the result's solid (the inner walls
    // of overlapping shells are absorbed, not lost)
    j["result_to_input"] = r.deviation.bToA;
    j["result_to_input_mean"] = r.deviation.meanBToA;
    j["input_to_result"] = r.lostDistance;
    j["deviation_bound"] = r.deviationBound;
    j["pieces_before"] = r.piecesBefore;
    j["pieces"] = r.after.components;
    j["departures"] = r.departures;
    j["actions"] = r.actions;
    j["reasons_before"] = r.before.reasons;
    j["reasons"] = verdict.reasons;
    std::cout << dumped(j);
  } else if (!quiet || !verdict.printable()) {
    std::cout << repairToText(r, verdict, displayName(input));
  }
  if (!verdict.printable()) {
    if (!json)
      std::cerr << "frepcad: " << displayName(input)
                << (written ? ": written although still not printable (--force)\n"
                            : ": could not be made printable (reasons above); nothing written "
                              "(--force writes it anyway)\n");
    return 1;
  }
  if (!r.departures.empty()) {
    if (!json)
      std::cerr << "frepcad: " << displayName(input)
                << (written ? ": written although not faithful to the input (--force)\n"
                            : ": the repair is not faithful to the input (reasons above); "
                              "nothing written (--max-deviation or --allow-pieces accept "
                              "it)\n");
    return 1;
  }
  if (!quiet && !json) std::cout << "wrote " << displayName(output) << "\n";
  return 0;
}

int compareCommand(const Args& args) {
  std::vector<std::string> files;
  bool json = false;
  for (const auto& a : args) {
    if (a == "-h" || a == "--help") {
      std::cout << "usage: frepcad compare A B [--json]\n\n"
                   "How far two meshes are apart: the Hausdorff distance both ways, sampled at\n"
                   "each mesh's vertices, face centres and random points (up to 60,000 each),\n"
                   "measured to the other's nearest triangle. Broken meshes are measured too.\n";
      return 0;
    }
    if (a == "--json")
      json = true;
    else if (!a.empty() && a[0] == '-')
      throw UsageError("unknown option '" + a + "' for compare");
    else
      files.push_back(a);
  }
  if (files.size() != 2) throw UsageError("compare takes two mesh files");
  const DeviationReport d = meshDeviation(readMesh(files[0]), readMesh(files[1]));
  if (json) {
    nlohmann::json j;
    j["a"] = displayName(files[0]);
    j["b"] = displayName(files[1]);
    j["hausdorff"] = d.hausdorff();
    j["a_to_b"] = d.aToB;
    j["b_to_a"] = d.bToA;
    j["mean_a_to_b"] = d.meanAToB;
    j["mean_b_to_a"] = d.meanBToA;
    j["samples"] = d.samples;
    std::cout << dumped(j);
    return 0;
  }
  std::ostringstream os;
  os.precision(10);
  os << "compare " << displayName(files[0]) << " with " << displayName(files[1]) << "\n"
     << "  Hausdorff distance   " << d.hausdorff() << "\n"
     << "  A to B               " << d.aToB << " largest, " << d.meanAToB << " mean\n"
     << "  B to A               " << d.bToA << " largest, " << d.meanBToA << " mean\n"
     << "  points sampled       " << d.samples << "\n";
  std::cout << os.str();
  return 0;
}

}  // namespace frep::cli

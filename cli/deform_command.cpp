// frepcad deform: a lattice file applied to a mesh (vertices pushed forward) or to every grid
// of a .vdb file (backward resampling, no gaps), checked and written atomically.
#include <unistd.h>

#include <iostream>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "cli/commands.h"
#include "cli/terminal_progress.h"
#include "io/mesh_io.h"
#include "lattice/lattice_file.h"
#include "mesh/mesh_ffd.h"
#include "volume/grid_ffd.h"
#include "volume/grid_set.h"

namespace frep::cli {

namespace {

const char* const kDeformHelp =
    "usage: frepcad deform IN.stl|IN.obj|IN.ply|IN.off|IN.vdb --lattice LATTICE.json -o OUT\n"
    "                      [--format stl|stl-ascii|obj|ply|bms] [--force] [--quiet]\n"
    "                      [--interpolation nearest|linear|quadratic] [--keep-vectors]\n"
    "                      [--no-rebuild] [--splat]\n\n"
    "Deforms a mesh or every grid of an OpenVDB file by a lattice (the format is in\n"
    "docs/file-formats.md, \"Lattice files\").\n"
    "  a mesh: every vertex inside the rest box moves with the lattice; the result is\n"
    "          checked like every export and refused when it is not printable\n"
    "  a .vdb: every voxel of each deformed grid is pulled back through the lattice's\n"
    "          inverse and samples the source there, so stretching leaves no gaps;\n"
    "          level sets are rebuilt as signed distances afterwards\n"
    "  --interpolation M     how grid values are sampled (default linear; int32 and bool\n"
    "                        grids always take the nearest voxel)\n"
    "  --keep-vectors        copy vector values as they are instead of transforming them\n"
    "                        by the lattice's Jacobian\n"
    "  --no-rebuild          leave deformed level sets as resampled, not rebuilt\n"
    "  --splat               seed 002's forward splatting instead (for comparison: it\n"
    "                        leaves gaps where the lattice stretches)\n"
    "  --force               write a mesh even when the check refuses it (exit status 1)\n"
    "exit status: 0 written, 1 the mesh is not printable (nothing written without --force),\n"
    "2 bad input, 130 cancelled\n";

}  // namespace

int deformCommand(const Args& args) {
  std::string input, output, latticePath, format;
  GridFfdOptions gridOptions;
  bool force = false, quiet = false, meshOnly = false, gridOnly = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      std::cout << kDeformHelp;
      return 0;
    } else if (a == "-o" || a == "--output")
      output = value();
    else if (a == "--lattice")
      latticePath = value();
    else if (a == "--format")
      format = value(), meshOnly = true;
    else if (a == "--force")
      force = true, meshOnly = true;
    else if (a == "--quiet")
      quiet = true;
    else if (a == "--keep-vectors")
      gridOptions.keepVectors = true, gridOnly = true;
    else if (a == "--no-rebuild")
      gridOptions.rebuildLevelSets = false, gridOnly = true;
    else if (a == "--splat")
      gridOptions.method = GridFfdOptions::Method::ForwardSplat, gridOnly = true;
    else if (a == "--interpolation") {
      const std::string& m = value();
      gridOnly = true;
      if (m == "nearest")
        gridOptions.interpolation = 0;
      else if (m == "linear")
        gridOptions.interpolation = 1;
      else if (m == "quadratic")
        gridOptions.interpolation = 2;
      else
        throw UsageError("--interpolation expects nearest, linear or quadratic, got '" + m + "'");
    } else if (!a.empty() && a[0] == '-' && a.size() > 1)
      throw UsageError("unknown option '" + a + "' for deform (see frepcad deform --help)");
    else if (input.empty())
      input = a;
    else
      throw UsageError("deform takes one input file, got a second: '" + a + "'");
  }
  if (input.empty()) throw UsageError("deform needs an input file (a mesh or a .vdb)");
  if (output.empty()) throw UsageError("deform needs -o OUT");
  if (latticePath.empty()) throw UsageError("deform needs --lattice LATTICE.json");
  const bool vdb = isVdbPath(input);
  if (vdb != isVdbPath(output))
    throw UsageError(vdb ? "a .vdb input deforms into a .vdb output"
                         : "a mesh deforms into a mesh, not a .vdb");
  if (vdb && meshOnly) throw UsageError("--format and --force apply to meshes, not to .vdb files");
  if (!vdb && gridOnly)
    throw UsageError(
        "--interpolation, --keep-vectors, --no-rebuild and --splat apply to .vdb files");
  checkOutputPath(output, input);
  // Everything that can be refused is refused before the work: the format, the lattice.
  const MeshFormat meshFormat = vdb              ? MeshFormat::StlBinary
                                : format.empty() ? formatFromPath(output)
                                                 : parseFormat(format);
  const FfdLattice lattice = readLatticeFile(latticePath);
  if (auto fold = lattice.findFold()) throw ModelError(latticePath + ": " + fold->text());

  installInterruptHandlers();
  TerminalProgress bar(!quiet && isatty(STDERR_FILENO));
  auto progress = [&bar](double f) { return bar(ExportStage::Mesh, f); };
  if (vdb) {
    const GridSet grids = readVdb(input);
    gridOptions.progress = progress;
    const GridSet out = deformGrids(grids, lattice, gridOptions);
    writeVdb(out, output);
    if (!quiet) {
      std::cout << "deformed " << input << " by " << latticePath << " (" << lattice.divisions(0)
                << " x " << lattice.divisions(1) << " x " << lattice.divisions(2) << ")\n";
      for (std::size_t g = 0; g < out.size(); ++g)
        std::cout << "  " << describeGrid(out.info(g)) << "\n";
      std::cout << "wrote " << output << "\n";
    }
    return 0;
  }
  const TriangleMesh mesh = readMesh(input);
  MeshFfdOptions meshOptions;
  meshOptions.progress = progress;
  const TriangleMesh out = deformMesh(mesh, lattice, meshOptions);
  const CheckReport report = checkMesh(out);
  if (!quiet || !report.printable()) std::cout << reportToText(report, output);
  if (!report.printable() && !force) {
    std::cerr
        << "frepcad: refusing to write " << output
        << ": the deformed mesh is not printable (see reasons above; --force writes it anyway)\n";
    return 1;
  }
  writeMesh(out, output, meshFormat);
  if (!quiet) std::cout << "wrote " << output << " (" << formatName(meshFormat) << ")\n";
  return report.printable() ? 0 : 1;
}

}  // namespace frep::cli

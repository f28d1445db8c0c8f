// `frepcad export`: one set of options for JSON models and FreeCAD documents, one pipeline
// (libcore/pipeline) behind both.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>

#include "base/errors.h"
#include "base/file_names.h"
#include "cli/commands.h"
#include "cli/heavy_module.h"
#include "cli/mesh_settings_flags.h"
#include "cli/terminal_progress.h"
#include "frep/model_json.h"
#include "frep/structural_bounds.h"
#include "pipeline/beam_export.h"
#include "pipeline/brick_jobs.h"
#include "pipeline/export_pipeline.h"

namespace frep::cli {

const char* const kExportHelp =
    "usage: frepcad export INPUT -o OUT [options]\n"
    "\n"
    "Meshes a model (INPUT.json) or a FreeCAD document made with the FRep workbench\n"
    "(INPUT.FCStd, exported by FreeCAD headless), checks the mesh with CGAL and writes OUT\n"
    "through a temporary file: a mesh the check refuses, an error or Ctrl-C leave no file.\n"
    "\n"
    "options (for both kinds of input):\n"
    "  -o, --output OUT        the mesh file (.stl, .obj, .ply, .3mf, .bms), or .vdb: an OpenVDB "
    "level\n"
    "                          set of the solid (one voxel per cell, narrow band of 3 voxels)\n"
    "  --resolution R          cell size (default: the model's, else the box's longest side / "
    "128)\n"
    "  --cells N               cells along the longest side of the box, instead of --resolution\n"
    "  --bbox X0 Y0 Z0 X1 Y1 Z1  meshing box (default: the model's, else the solid's own box)\n"
    "  --format F              stl, stl-ascii, obj, ply, bms or 3mf (default: from OUT's\n"
    "                          extension)\n"
    "  --units U               a 3MF's length unit: micron, mm, cm, inch, ft, m (default mm)\n"
    "meshing options (the same names in frepcore and the Polygonize feature):\n"
    "%MESHING%"
    "other options:\n"
    "  --fog                   with OUT.vdb: a fog volume (0 outside, 1 inside, a ramp across\n"
    "                          the band inside the surface) instead of a level set\n"
    "  --beams                 with OUT.3mf: a strut lattice's struts as a 3MF beam lattice\n"
    "                          (beams and radii, clipped by the part's mesh; an infill's skin\n"
    "                          as a mesh) instead of their triangles: the model's root is a\n"
    "                          strut_lattice cut to a part, or an infill with CELL_struts;\n"
    "                          the mesh simplified within --tolerance, by default a tenth of\n"
    "                          the resolution\n"
    "  --stats                 measure the mesh against the exact surface: the Hausdorff\n"
    "                          distance (sampled), the volume and the crease length\n"
    "  --force                 write the mesh even when the check refuses it (exit status 1)\n"
    "  --bricks N              mesh as N brick jobs on Dask distributed, weld them exactly,\n"
    "                          check and write (the same mesh as without; N = 8 or 64 cut\n"
    "                          the box into 2 or 4 jobs per axis; docs/distributed.md)\n"
    "  --scheduler ADDRESS     with --bricks: a Dask scheduler (tcp://HOST:8786); default: a\n"
    "                          local cluster with one worker per core\n"
    "  --work-dir DIR          with --bricks: the folder for the jobs' pieces, reachable by\n"
    "                          every worker (default: beside OUT)\n"
    "  --quiet                 print nothing but errors\n"
    "  -h, --help              this text\n"
    "FreeCAD documents only:\n"
    "  --object NAME           the object to export (default: the only Polygonize feature or\n"
    "                          top-level FRep feature); repeat it for several: a 3MF holds\n"
    "                          each as its own object, other formats their union\n"
    "  --set OBJ.PROP=VALUE    set a property (or a spreadsheet cell: Sheet.Alias=VALUE) first;\n"
    "                          may be repeated\n"
    "\n"
    "exit status: 0 written, 1 the mesh is not printable (nothing written without --force),\n"
    "2 bad input (one line naming the file, object, parameter and what is allowed),\n"
    "3 internal error (a bug: please report it), 130 cancelled (Ctrl-C, SIGTERM).\n";

namespace {

namespace fs = std::filesystem;

// "(x, y, z)", for the accuracy report.
std::string point(const Vec3& p) {
  std::ostringstream os;
  os << "(" << p[0] << ", " << p[1] << ", " << p[2] << ")";
  return os.str();
}

ExportOptions parseExportOptions(const Args& args) {
  ExportOptions o;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](const char* what) -> const std::string& {
      if (i + 1 >= args.size()) throw UsageError(a + " expects " + what);
      return args[++i];
    };
    if (a == "-h" || a == "--help")
      o.help = true;
    else if (a == "-o" || a == "--output")
      o.output = value("an output file");
    else if (a == "--resolution") {
      o.resolution = parseNumber(value("a cell size"), a);
      if (!(*o.resolution > 0) || !std::isfinite(*o.resolution))
        throw UsageError("--resolution must be a number > 0, got '" + args[i] + "'");
    } else if (a == "--cells") {
      const double n = parseNumber(value("a number of cells"), a);
      if (!(n >= 1 && n <= kMaxCells && n == std::floor(n)))
        throw UsageError("--cells must be a whole number from 1 to " + std::to_string(kMaxCells) +
                         ", got '" + args[i] + "'");
      o.cells = static_cast<int>(n);
    } else if (takeMeshSettingFlag(args, i, o.mesh, o.meshGiven)) {
    } else if (a == "--stats")
      o.stats = true;
    else if (a == "--fog")
      o.fog = true;
    else if (a == "--beams")
      o.beams = true;
    else if (a == "--format")
      o.format = value("a format");
    else if (a == "--units")
      o.units = value("a unit (micron, mm, cm, inch, ft, m)");
    else if (a == "--force")
      o.force = true;
    else if (a == "--quiet")
      o.quiet = true;
    else if (a == "--object")
      o.objects.push_back(value("an object name"));
    else if (a == "--set")
      o.sets.push_back(value("Object.Property=VALUE"));
    else if (a == "--bricks") {
      const std::string& n = value("a number of brick jobs");
      const double v = parseNumber(n, a);
      if (!(v >= 1 && v <= 65536) || v != std::floor(v))
        throw UsageError("--bricks must be a whole number of jobs from 1 to 65536, got '" + n +
                         "'");
      o.bricks = static_cast<int>(v);
    } else if (a == "--scheduler")
      o.scheduler = value("a Dask scheduler address (tcp://HOST:8786)");
    else if (a == "--work-dir")
      o.workDir = value("a folder every worker can reach");
    else if (a == "--bbox") {
      Box3 b;
      for (int k = 0; k < 6; ++k) {
        const double v = parseNumber(value("6 numbers x0 y0 z0 x1 y1 z1"), a);
        if (!std::isfinite(v)) throw UsageError("--bbox needs finite numbers");
        (k < 3 ? b.lo[k] : b.hi[k - 3]) = v;
      }
      if (!b.valid()) throw UsageError("--bbox needs x0 < x1, y0 < y1, z0 < z1");
      o.bbox = b;
    } else if (!a.empty() && a[0] == '-' && a.size() > 1)
      throw UsageError("unknown option '" + a + "' for export (see frepcad export --help)");
    else if (o.input.empty())
      o.input = a;
    else
      throw UsageError("export takes one input file, got a second: '" + a + "'");
  }
  if (o.help) return o;
  if (o.input.empty()) throw UsageError("export needs an input file (MODEL.json or DOC.FCStd)");
  if (o.output.empty()) throw UsageError("export needs -o OUT");
  if (o.resolution && o.cells) throw UsageError("give --resolution or --cells, not both");
  if (o.fog && !isVdbPath(o.output)) throw UsageError("--fog applies to a .vdb output only");
  if ((!o.scheduler.empty() || !o.workDir.empty()) && !o.bricks)
    throw UsageError("--scheduler and --work-dir apply to --bricks only");
  validateMeshFlags(o.mesh);
  if (o.beams) {
    const std::string format = o.format.empty() ? std::string() : o.format;
    if ((!format.empty() && format != "3mf") ||
        (format.empty() && formatFromPath(o.output) != MeshFormat::ThreeMf))
      throw UsageError("--beams writes a 3MF beam lattice: give OUT.3mf");
    if (o.bricks || o.stats)
      throw UsageError("--beams cannot be combined with --bricks or --stats");
    if (isDocumentPath(o.input))
      throw UsageError("--beams applies to JSON models; export the document's model first");
  }
  if (isVdbPath(o.output) && !o.meshGiven.empty())
    throw UsageError(settingFlag(*o.meshGiven.begin()) +
                     " applies to meshes, not to a .vdb level set");
  if (o.bricks) {
    // (the simplifier, the straightening and the accuracy report work on the whole mesh, a
    // brick job's refined cubes would change its neighbours' faces; a level set is OpenVDB's,
    // a document FreeCAD's)
    try {
      checkBrickJobSettings(o.mesh);
    } catch (const SettingError& e) {
      throw flagError(e);
    }
    if (o.stats) throw UsageError("--bricks cannot be combined with --stats yet");
    if (isVdbPath(o.output)) throw UsageError("--bricks writes meshes, not .vdb volumes");
    if (isDocumentPath(o.input))
      throw UsageError("--bricks applies to JSON models; export the document's model first");
  }
  return o;
}

// Parts of the solid thinner than the cell that the grid passed between with no surface near
// (docs/mesher.md, "Parts thinner than a cell"): the mesh is printable, but not all of the
// model. (Crease tips cut short are only in --stats: every crease has them.)
void printThinParts(const MeshingStats& stats, double cell) {
  if (stats.refinedCubes > 0)
    std::cerr << "frepcad: " << stats.refinedCubes
              << " cubes round parts thinner than a cell meshed again at half a cell\n";
  if (stats.refinedDeeperCubes > 0)
    std::cerr << "frepcad: " << stats.refinedDeeperCubes
              << " smaller cubes meshed again below that, down to a cell / "
              << (1 << stats.refinementLevelsReached) << "\n";
  if (!stats.refinementSkipped.empty())
    std::cerr << "frepcad: warning: the thin parts were not refined: " << stats.refinementSkipped
              << "\n";
  if (!stats.refinementDeeperSkipped.empty())
    std::cerr << "frepcad: warning: the thin parts were refined " << stats.refinementLevelsReached
              << " level(s) deep only: " << stats.refinementDeeperSkipped << "\n";
  if (stats.thinSolidEdges == 0 && stats.thinGapEdges == 0) return;
  const Vec3& p = stats.thinExample;
  if (stats.thinSolidEdges > 0)
    std::cerr << "frepcad: warning: solid thinner than a cell (" << cell << ") passes between "
              << "the grid's points at " << stats.thinSolidEdges
              << " grid edges: the mesh leaves it out there\n";
  if (stats.thinGapEdges > 0)
    std::cerr << "frepcad: warning: gaps narrower than a cell (" << cell << ") pass between "
              << "the grid's points at " << stats.thinGapEdges
              << " grid edges: the mesh closes them there\n";
  std::cerr << "  for example at (" << p[0] << ", " << p[1] << ", " << p[2]
            << "); more cells (--cells or --resolution) keep more of the model\n";
}

// --beams: the strut lattice as a 3MF beam lattice (pipeline/beam_export.h).
int exportBeams(const ExportOptions& opt, const Model& model, const MeshingBox& box,
                const ThreeMfOptions& threeMf) {
  installInterruptHandlers();
  BeamExportResult r;
  {
    TerminalProgress bar(!opt.quiet && isatty(STDERR_FILENO));
    r = exportBeamLattice(model.root, box, opt.mesh, threeMf, fs::path(opt.input).stem().string(),
                          opt.output, opt.force,
                          [&bar](double f) { return bar(ExportStage::Mesh, f); });
  }
  if (r.clipped && !r.clipReport.printable())
    std::cout << reportToText(r.clipReport, "the part's mesh");
  if (r.skinTriangles && !r.skinReport.printable())
    std::cout << reportToText(r.skinReport, "the infill's skin");
  if (!r.written) {
    std::cerr << "frepcad: refusing to write " << opt.output
              << ": a mesh of the beam lattice's file is not printable (see reasons above; "
                 "--force writes it anyway)\n";
    return 1;
  }
  if (!r.notes.empty() && !opt.quiet) std::cerr << "frepcad: note: " << r.notes << "\n";
  if (!opt.quiet) {
    const ThreeMfBeams back = read3mfBeams(opt.output);
    std::cout << "wrote " << opt.output << " (3mf beam lattice): " << beamExportSummary(r)
              << "; lib3mf reads " << back.beams << " beams back, " << r.seconds << " s\n";
  }
  return 0;
}

int exportModel(const ExportOptions& opt) {
  const Model model = loadModel(opt.input);
  const Program program = compile(model.root);
  const bool vdb = isVdbPath(opt.output);
  // The format first: a bad output name or format is refused before the work.
  const MeshFormat format = vdb                  ? MeshFormat::StlBinary
                            : opt.format.empty() ? formatFromPath(opt.output)
                                                 : parseFormat(opt.format);

  BoxRequest box;
  box.bbox = opt.bbox ? opt.bbox : model.bbox;
  box.resolution = opt.resolution;
  box.cells = opt.cells;
  if (!box.resolution && !box.cells) box.resolution = model.resolution;
  ExportRequest request;
  request.box = box;
  request.known = structuralBounds(model.root);
  request.format = format;
  if (!opt.units.empty()) {
    if (format != MeshFormat::ThreeMf) throw UsageError("--units applies to a 3MF output only");
    request.threeMf.unit = parseLengthUnit(opt.units);
  }
  request.threeMf.metadata = {{"Application", "FRepCAD frepcad export"},
                              {"Title", fs::path(opt.input).stem().string()}};
  request.force = opt.force;
  request.mesh = opt.mesh;
  request.stats = opt.stats;
  // The box policy is the pipeline's; the CLI only adds where the user gives a box.
  MeshingBox chosen;
  try {
    chosen = chooseBox(program, request.known, box);
    request.box.bbox = chosen.box;
    request.box.resolution = chosen.resolution;
  } catch (const EmptySolidError& e) {
    throw EmptySolidError(opt.input + ": " + e.what());
  } catch (const ModelError& e) {
    std::string text = e.what();
    const bool unbounded = text.find("unbounded") != std::string::npos;
    if (!unbounded || !model.fallbackBox || box.bbox) {
      if (unbounded)
        text += " (frepcad export --bbox x0 y0 z0 x1 y1 z1, or export.bbox in the model)";
      throw ModelError(opt.input + ": " + text);
    }
    box.bbox = model.fallbackBox;
    chosen = chooseBox(program, request.known, box);
    request.box.bbox = chosen.box;
    request.box.resolution = chosen.resolution;
    const Box3& b = *model.fallbackBox;
    if (!opt.quiet)
      std::cerr << "frepcad: " << opt.input << ": the solid's extent could not be found; "
                << "meshing the box " << b.lo[0] << " " << b.lo[1] << " " << b.lo[2] << " "
                << b.hi[0] << " " << b.hi[1] << " " << b.hi[2]
                << " (HyperFun's; --bbox to choose another)\n";
  }
  if (vdb) return heavyModule().exportLevelSet(opt, program, chosen);
  if (opt.beams) return exportBeams(opt, model, chosen, request.threeMf);
  if (opt.bricks)
    return exportDistributed(opt, chosen.box, chosen.resolution, request.threeMf.metadata);

  installInterruptHandlers();
  ExportResult r;
  {
    TerminalProgress bar(!opt.quiet && isatty(STDERR_FILENO));
    request.progress = [&bar](ExportStage s, double f) { return bar(s, f); };
    try {
      r = exportField(program, request, opt.output, opt.input);
    } catch (const TooLargeError& e) {
      // too large for this process: brick jobs keep every process small
      throw ModelError(std::string(e.what()) +
                       "; or mesh it as brick jobs across processes "
                       "or machines: --bricks 64 (docs/distributed.md)");
    }
  }
  if (!opt.quiet)
    std::cout << "meshed " << opt.input << ": " << r.triangles << " triangles, grid "
              << r.stats.cells[0] << "x" << r.stats.cells[1] << "x" << r.stats.cells[2] << ", "
              << r.seconds[1] << " s (check " << r.seconds[2] << " s)\n";
  if (!opt.quiet && r.simplified)
    std::cout << "simplified " << r.simplify.trianglesBefore << " -> " << r.simplify.trianglesAfter
              << " triangles in " << r.simplify.seconds << " s, the faces it made within "
              << r.simplify.largestDistance << " of the exact surface (tolerance "
              << *opt.mesh.tolerance
              << (r.simplify.largestDistance > *opt.mesh.tolerance
                      ? "; where the grid had cut a crease off by more, only made better)\n"
                      : ")\n");
  if (!opt.quiet && r.straightened)
    std::cout << "straightened creases: " << r.straighten.collapses
              << " vertices merged onto them and " << r.straighten.flips
              << " edges flipped along them (" << r.straighten.trianglesBefore << " -> "
              << r.straighten.trianglesAfter << " triangles) in " << r.straighten.seconds << " s\n";
  printThinParts(r.stats, r.box.resolution);
  if (r.simplificationRefused)
    std::cerr << "frepcad: warning: the simplified or straightened mesh failed the check (a bug: "
                 "please report it with the model); the mesher's own, which passed, is written\n";
  if (!opt.quiet || !r.report.printable()) std::cout << reportToText(r.report, opt.output);
  if (r.accuracy) {
    const AccuracyReport& a = *r.accuracy;
    const double cell = r.box.resolution;
    std::cout << "accuracy (" << a.samples << " points sampled through the function)\n"
              << "  Hausdorff distance   " << a.hausdorff << " (" << a.hausdorff / cell
              << " cells)\n"
              << "  mesh to surface      " << a.meshToSurface << " largest, " << a.meshToSurfaceMean
              << " mean"
              << (a.unreached ? " (" + std::to_string(a.unreached) +
                                    " points measured to the sampled surface)"
                              : std::string())
              << "\n"
              << "                       largest at " << point(a.meshToSurfaceAt) << "\n"
              << "  surface to mesh      " << a.surfaceToMesh << " largest\n"
              << "                       largest at " << point(a.surfaceToMeshAt) << "\n"
              << "  volume               " << a.volume << "\n"
              << "  crease length        " << a.creaseLength << " (edges whose faces turn by over "
              << AccuracyOptions().creaseAngleDeg << " degrees)\n"
              << "  thinner than a cell  grid edges crossed between two grid points: "
              << r.stats.thinSolidEdges << " solid, " << r.stats.thinGapEdges
              << " gaps (no surface near), " << r.stats.tipEdges << " tips\n";
  }
  if (!r.written) {
    std::cerr << "frepcad: refusing to write " << opt.output
              << ": the mesh is not printable (see reasons above; --force writes it anyway)\n";
    return 1;
  }
  if (!opt.quiet) std::cout << "wrote " << opt.output << " (" << formatName(format) << ")\n";
  return r.report.printable() ? 0 : 1;
}

}  // namespace

// The output must be a regular file name (or not exist yet), and not the input itself.
void checkOutputPath(const std::string& output, const std::string& input) {
  std::error_code ec;
  const fs::path out = output;
  const fs::file_status st = fs::symlink_status(out, ec);
  if (fs::exists(st)) {
    if (fs::is_symlink(st))
      throw FileError(output +
                      ": is a symbolic link; give the name of a regular file (the "
                      "output replaces the file, not the link's target)");
    if (fs::is_directory(st)) throw FileError(output + ": is a folder; give a file name");
    if (!fs::is_regular_file(st))
      throw FileError(output + ": is a device, FIFO or socket; give a regular file name");
    if (fs::equivalent(out, fs::path(input), ec))
      throw FileError(output + ": is the input itself; give another output name");
  }
}

int exportCommand(const Args& args) {
  const ExportOptions opt = parseExportOptions(args);
  if (opt.help) {
    std::string help = kExportHelp;
    help.replace(help.find("%MESHING%"), 9, meshSettingsHelp());
    std::cout << help;
    return 0;
  }
  checkOutputPath(opt.output, opt.input);
  if (isDocumentPath(opt.input)) return exportDocument(opt);
  if (!opt.objects.empty() || !opt.sets.empty())
    throw UsageError("--object and --set apply to FreeCAD documents (.FCStd) only");
  return exportModel(opt);
}

}  // namespace frep::cli

// frepcad hspline: hierarchical B-spline surfaces from the command line (docs/hsplines.md):
// make one, look at it, refine, move, zero offsets, unrefine, export it as STEP, as a checked
// mesh or as an (optimised) .hs file, and fill a shell along it with a strut lattice. Every
// write is atomic.
#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "base/atomic_file.h"
#include "base/errors.h"
#include "check/mesh_check.h"
#include "cli/commands.h"
#include "frep/model_json.h"
#include "frep/registry.h"
#include "hspline/hs_file.h"
#include "hspline/hspline_flatten.h"
#include "hspline/hspline_select.h"
#include "hspline/hspline_shapes.h"
#include "hspline/hspline_tessellate.h"
#include "hspline/occt/occ_hspline.h"
#include "io/mesh_io.h"
#include "pipeline/hspline_shell.h"

namespace frep::cli {

namespace {

const char* const kHsplineHelp =
    "usage: frepcad hspline new plane|cylinder|torus -o OUT.hs [--cvs NU NV]\n"
    "                          [--size U V] [--radius R] [--height H] [--tube r]\n"
    "       frepcad hspline info IN.hs [--json]\n"
    "       frepcad hspline refine IN.hs -o OUT.hs --level L (--cv I J ... | --all |\n"
    "                          --region U0 U1 V0 V1)\n"
    "       frepcad hspline move IN.hs -o OUT.hs --cv L I J (--to X Y Z | --by DX DY DZ)\n"
    "       frepcad hspline zero IN.hs -o OUT.hs (--cv L I J ... | --level L)\n"
    "       frepcad hspline unrefine IN.hs -o OUT.hs\n"
    "       frepcad hspline export IN.hs -o OUT.step|OUT.stl|OUT.3mf|OUT.obj|OUT.ply|OUT.hs\n"
    "                          [--tolerance D] [--optimised] [--force] [--quiet]\n"
    "       frepcad hspline lattice IN.hs -o OUT.json --thickness T [--divisions L M]\n"
    "                          [--cell-type octet] [--cell C] [--radius R] [--straight]\n"
    "                          [--quiet]\n\n"
    "Hierarchical B-spline surfaces (.hs files, docs/file-formats.md):\n"
    "  new        level 0 of a plane (default 8 x 8 CVs, 100 x 100), a cylinder (8 x 8,\n"
    "             r 20, 60 high) or a torus (10 x 8, radii 30 and 10)\n"
    "  refine     a finer level around CVs of level L (7 x 7 new CVs about each); the\n"
    "             surface does not change\n"
    "  move       a CV to a point or by a vector; a fixed CV is refused with the reason\n"
    "  zero       CVs of refined levels back onto their parent surface\n"
    "  unrefine   removes CVs with zero offset that no detail needs; the surface stays\n"
    "  export     .step through OpenCASCADE (a solid when the hspline is closed); a mesh\n"
    "             within --tolerance (default 0.01) of the surface, checked, written only\n"
    "             when printable (or --force); .hs again, --optimised leaves unused CVs out\n"
    "  lattice    a model (JSON) of a strut lattice whose cells follow the surface: a\n"
    "             shell --thickness thick, cells of C (default half the thickness) along\n"
    "             the surface's parameters, struts of R (default a tenth of a cell); an FFD\n"
    "             lattice of L x M divisions (default level 0's CVs less one, at most 24)\n"
    "             fitted to the surface carries them (the struts curving with it, or\n"
    "             --straight between their ends); export it meshed or --beams\n"
    "exit status: 0 done, 1 the mesh is not printable (nothing written without --force),\n"
    "2 bad input\n";

struct Options {
  std::string verb, input, output, shape;
  std::vector<std::vector<double>> cvs;  // --cv values, as given
  std::vector<double> region, to, by, size, counts;
  std::optional<int> level;
  std::optional<double> radius, height, tube, tolerance, thickness, cell;
  std::vector<double> divisions;
  std::string cellType = "octet";
  bool all = false, json = false, optimised = false, force = false, quiet = false;
  bool straight = false;
};

std::vector<double> numbers(const Args& args, std::size_t& i, std::size_t n,
                            const std::string& option) {
  std::vector<double> out;
  for (std::size_t k = 0; k < n; ++k) {
    if (i + 1 >= args.size()) throw UsageError(option + " needs " + std::to_string(n) + " numbers");
    out.push_back(parseNumber(args[++i], option));
  }
  return out;
}

int whole(double x, const std::string& what) {
  if (x != static_cast<int>(x)) {
    std::ostringstream got;  // 2.5, not to_string's 2.500000
    got << x;
    throw UsageError(what + " must be a whole number, got " + got.str());
  }
  return static_cast<int>(x);
}

Options parse(const Args& args) {
  Options o;
  if (args.empty())
    throw UsageError(
        "hspline needs a verb: new, info, refine, move, zero, unrefine, export, lattice");
  o.verb = args[0];
  static const std::set<std::string> verbs{"new",  "info",     "refine", "move",
                                           "zero", "unrefine", "export", "lattice"};
  if (o.verb == "-h" || o.verb == "--help") return o;
  if (!verbs.count(o.verb))
    throw UsageError("unknown hspline verb '" + o.verb +
                     "'; verbs: new, info, refine, move, zero, unrefine, export, lattice");
  // The options each verb uses: another verb's option is refused, not silently ignored
  // (`unrefine --level 2` would otherwise unrefine every level).
  static const std::map<std::string, std::string> verbOptions{
      {"new",
       "-o --output --cvs --size --radius --height --tube --optimised --optimized --force --quiet"},
      {"info", "--json"},
      {"refine", "-o --output --level --cv --all --region --optimised --optimized --force --quiet"},
      {"move", "-o --output --cv --to --by --optimised --optimized --force --quiet"},
      {"zero", "-o --output --cv --level --optimised --optimized --force --quiet"},
      {"unrefine", "-o --output --optimised --optimized --force --quiet"},
      {"export", "-o --output --tolerance --optimised --optimized --force --quiet"},
      {"lattice",
       "-o --output --thickness --divisions --cell-type --cell --radius --straight --quiet"}};
  const std::string& mine = verbOptions.at(o.verb);
  auto takes = [&](const std::string& opt) {
    return (" " + mine + " ").find(" " + opt + " ") != std::string::npos;
  };
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto one = [&]() { return numbers(args, i, 1, a)[0]; };
    const bool someVerbTakes =
        std::any_of(verbOptions.begin(), verbOptions.end(), [&](const auto& v) {
          return (" " + v.second + " ").find(" " + a + " ") != std::string::npos;
        });
    if (someVerbTakes && !takes(a))
      throw UsageError("hspline " + o.verb + " does not take " + a + "; its options: " + mine);
    if (a == "-h" || a == "--help") {
      o.verb = "--help";
      return o;
    } else if (a == "-o" || a == "--output") {
      if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
      o.output = args[++i];
    } else if (a == "--cv")
      o.cvs.push_back(numbers(args, i, o.verb == "refine" ? 2 : 3, a));
    else if (a == "--level")
      o.level = whole(one(), "--level");
    else if (a == "--region")
      o.region = numbers(args, i, 4, a);
    else if (a == "--to")
      o.to = numbers(args, i, 3, a);
    else if (a == "--by")
      o.by = numbers(args, i, 3, a);
    else if (a == "--cvs")
      o.counts = numbers(args, i, 2, a);
    else if (a == "--size")
      o.size = numbers(args, i, 2, a);
    else if (a == "--radius")
      o.radius = one();
    else if (a == "--height")
      o.height = one();
    else if (a == "--tube")
      o.tube = one();
    else if (a == "--tolerance")
      o.tolerance = one();
    else if (a == "--thickness")
      o.thickness = one();
    else if (a == "--cell")
      o.cell = one();
    else if (a == "--divisions")
      o.divisions = numbers(args, i, 2, a);
    else if (a == "--cell-type") {
      if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
      o.cellType = args[++i];
    } else if (a == "--all")
      o.all = true;
    else if (a == "--straight")
      o.straight = true;
    else if (a == "--json")
      o.json = true;
    else if (a == "--optimised" || a == "--optimized")
      o.optimised = true;
    else if (a == "--force")
      o.force = true;
    else if (a == "--quiet")
      o.quiet = true;
    else if (!a.empty() && a[0] == '-' && a.size() > 1)
      throw UsageError("unknown option '" + a + "' for hspline " + o.verb +
                       " (see frepcad hspline --help)");
    else if (o.verb == "new" && o.shape.empty())
      o.shape = a;
    else if (o.input.empty())
      o.input = a;
    else
      throw UsageError("hspline " + o.verb + " takes one input, got a second: '" + a + "'");
  }
  if (o.verb == "new") {
    if (o.shape != "plane" && o.shape != "cylinder" && o.shape != "torus")
      throw UsageError("hspline new makes a plane, a cylinder or a torus, not '" + o.shape + "'");
  } else if (o.input.empty()) {
    throw UsageError("hspline " + o.verb + " needs an input .hs file");
  }
  if (o.verb != "info" && o.output.empty()) throw UsageError("hspline " + o.verb + " needs -o OUT");
  return o;
}

HSpline make(const Options& o) {
  const int nu = o.counts.empty() ? (o.shape == "torus" ? 10 : 8) : whole(o.counts[0], "--cvs");
  const int nv = o.counts.empty() ? 8 : whole(o.counts[1], "--cvs");
  if (o.shape == "plane")
    return hsplinePlane(nu, nv, o.size.empty() ? 100 : o.size[0], o.size.empty() ? 100 : o.size[1]);
  if (o.shape == "cylinder")
    return hsplineCylinder(nu, nv, o.radius.value_or(20), o.height.value_or(60));
  return hsplineTorus(nu, nv, o.radius.value_or(30), o.tube.value_or(10));
}

void writeHs(const HSpline& h, const Options& o) {
  checkOutputPath(o.output, o.input);
  writeHsFile(h, o.output, o.optimised);
  if (!o.quiet)
    std::cout << "wrote " << o.output << " (" << h.levelCount() << " levels, " << h.cvCount()
              << " CVs)\n";
}

int info(const HSpline& h, const Options& o) {
  const FlatBSpline flat = flatten(h);
  const bool closed = h.level(0).u.isPeriodic() && h.level(0).v.isPeriodic();
  if (o.json) {
    std::cout << "{\"file\": \"" << o.input << "\", \"levels\": [";
    for (int l = 0; l < h.levelCount(); ++l)
      std::cout << (l ? ", " : "") << "{\"level\": " << l << ", \"grid\": [" << h.level(l).u.count()
                << ", " << h.level(l).v.count() << "], \"cvs\": " << h.level(l).cvs.size()
                << ", \"movable\": " << selectMovable(h, l).size()
                << ", \"non_zero\": " << (l ? selectNonZeroOffsets(h, l).size() : 0) << "}";
    std::cout << "], \"cvs\": " << h.cvCount() << ", \"closed\": " << (closed ? "true" : "false")
              << ", \"flattened_poles\": [" << flat.u.count() << ", " << flat.v.count() << "]}\n";
    return 0;
  }
  std::cout << o.input << ": " << h.levelCount() << " levels, " << h.cvCount() << " CVs, "
            << (closed ? "closed (a solid)" : "open (a sheet)") << "\n";
  const HsLevel& base = h.level(0);
  std::cout << "  u: " << (base.u.isPeriodic() ? "periodic" : "open") << ", domain [" << base.u.lo()
            << ", " << base.u.hi() << "];  v: " << (base.v.isPeriodic() ? "periodic" : "open")
            << ", domain [" << base.v.lo() << ", " << base.v.hi() << "]\n";
  for (int l = 0; l < h.levelCount(); ++l) {
    std::cout << "  level " << l << ": grid " << h.level(l).u.count() << " x "
              << h.level(l).v.count() << ", " << h.level(l).cvs.size() << " CVs, "
              << selectMovable(h, l).size() << " movable";
    if (l) std::cout << ", " << selectNonZeroOffsets(h, l).size() << " with an offset";
    std::cout << "\n";
  }
  std::cout << "  flattened: one B-spline of " << flat.u.count() << " x " << flat.v.count()
            << " poles\n";
  return 0;
}

std::vector<HsCvRef> refsOf(const Options& o) {
  std::vector<HsCvRef> out;
  for (const auto& c : o.cvs)
    out.push_back({whole(c[0], "--cv level"), whole(c[1], "--cv i"), whole(c[2], "--cv j")});
  return out;
}

int exportHs(const HSpline& h, const Options& o) {
  checkOutputPath(o.output, o.input);
  const std::string ext = o.output.size() > 3 ? o.output.substr(o.output.rfind('.') + 1) : "";
  if (ext == "hs") return writeHs(h, o), 0;
  if (ext == "step" || ext == "stp") {
    const OccShapeSummary s = writeHsStep(h, o.output);
    if (!o.quiet)
      std::cout << "wrote " << o.output << ": " << (s.solids ? "a solid" : "a face") << ", area "
                << s.area << (s.solids ? ", volume " + std::to_string(s.volume) : std::string())
                << "\n";
    return 0;
  }
  const MeshFormat format = formatFromPath(o.output);
  const double tolerance = o.tolerance.value_or(0.01);
  const HsTessellation t = tessellate(flatten(h), tolerance);
  const CheckReport report = checkMesh(t.mesh);
  if (!o.quiet || !report.printable()) std::cout << reportToText(report, o.output);
  if (!report.printable() && !o.force) {
    std::cerr << "frepcad: refusing to write " << o.output << ": the mesh is not printable"
              << (t.closed ? ""
                           : " (an open hspline is a sheet, not a solid: export .step, or --force)")
              << "\n";
    return 1;
  }
  writeMesh(t.mesh, o.output, format);
  if (!o.quiet)
    std::cout << "wrote " << o.output << " (" << t.mesh.triangles.size() << " triangles)\n";
  return report.printable() ? 0 : 1;
}

// A strut lattice in a shell along the surface (pipeline/hspline_shell.h).
int latticeAlongHspline(const HSpline& h, const Options& o) {
  if (!o.thickness) throw UsageError("hspline lattice needs --thickness T, the shell's thickness");
  checkOutputPath(o.output, o.input);
  HsplineShellSettings settings;
  settings.thickness = *o.thickness;
  settings.cell = o.cell.value_or(0.0);
  settings.cellType = o.cellType;
  settings.radius = o.radius.value_or(0.0);
  settings.straight = o.straight;
  if (!o.divisions.empty()) {
    settings.divisionsU = whole(o.divisions[0], "--divisions");
    settings.divisionsV = whole(o.divisions[1], "--divisions");
  }
  const HsplineShell shell = hsplineShellLattice(h, settings, o.input);
  const std::string json = modelToJson(shell.model);
  AtomicFile file(o.output);
  file.write(json.data(), json.size());
  file.commit();
  if (!o.quiet)
    std::cout << "wrote " << o.output << ": " << o.cellType << " cells of "
              << numberText(shell.cells[0]) << " x " << numberText(shell.cells[1]) << " x "
              << numberText(shell.cells[2]) << " in a shell " << numberText(settings.thickness)
              << " thick along " << o.input << " (" << numberText(shell.size[0]) << " x "
              << numberText(shell.size[1]) << " along its parameters); the FFD lattice of "
              << shell.divisions[0] << " x " << shell.divisions[1]
              << " divisions follows it within " << numberText(shell.deviation)
              << (shell.deviation > 0.05 * settings.thickness
                      ? "; more --divisions follow it closer (and take longer to mesh)"
                      : "")
              << "\n";
  return 0;
}

}  // namespace

int hsplineCommand(const Args& args) {
  const Options o = parse(args);
  if (o.verb == "-h" || o.verb == "--help") {
    std::cout << kHsplineHelp;
    return 0;
  }
  if (o.verb == "new") return writeHs(make(o), o), 0;
  HSpline h = readHsFile(o.input);
  if (o.verb == "info") return info(h, o);
  if (o.verb == "export") return exportHs(h, o);
  if (o.verb == "lattice") return latticeAlongHspline(h, o);
  if (o.verb == "refine") {
    if (!o.level) throw UsageError("hspline refine needs --level L, the level whose CVs to refine");
    std::vector<std::pair<int, int>> cvs;
    if (o.all)
      for (const HsCvRef& c : selectLevel(h, *o.level)) cvs.push_back({c.i, c.j});
    else if (!o.region.empty())
      for (const HsCvRef& c :
           selectRegion(h, *o.level, o.region[0], o.region[1], o.region[2], o.region[3]))
        cvs.push_back({c.i, c.j});
    for (const auto& c : o.cvs) cvs.push_back({whole(c[0], "--cv i"), whole(c[1], "--cv j")});
    if (cvs.empty())
      throw UsageError(
          "hspline refine needs --cv I J, --all or --region U0 U1 V0 V1 with CVs in it");
    h.refine(*o.level, cvs);
  } else if (o.verb == "move") {
    const auto refs = refsOf(o);
    if (refs.size() != 1) throw UsageError("hspline move needs one --cv L I J");
    if (o.to.empty() == o.by.empty())
      throw UsageError("hspline move needs --to X Y Z or --by DX DY DZ");
    const HsCvRef& c = refs[0];
    if (!h.find(c.level, c.i, c.j))
      throw ModelError("hspline move: there is no " + hsCvName(c.level, c.i, c.j));
    Vec3 target = o.to.empty() ? h.position(c.level, c.i, c.j) : Vec3{o.to[0], o.to[1], o.to[2]};
    if (!o.by.empty()) target = vadd(target, {o.by[0], o.by[1], o.by[2]});
    h.moveCv(c.level, c.i, c.j, target);
  } else if (o.verb == "zero") {
    std::vector<HsCvRef> refs = refsOf(o);
    if (o.level) {
      const auto level = selectLevel(h, *o.level);
      refs.insert(refs.end(), level.begin(), level.end());
    }
    if (refs.empty()) throw UsageError("hspline zero needs --cv L I J or --level L");
    h.zeroOffsets(refs);
  } else if (o.verb == "unrefine") {
    const std::size_t removed = h.unrefine();
    if (!o.quiet) std::cout << "unrefine removed " << removed << " CVs\n";
  }
  writeHs(h, o);
  return 0;
}

}  // namespace frep::cli

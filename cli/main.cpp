// frepcad: export FRep models to checked meshes, check mesh files, list node types.
#include <csignal>
#include <cstdio>
#include <iostream>

#include "base/errors.h"
#include "base/exit_status.h"
#include "base/process_memory.h"
#include "cli/commands.h"
#include "cli/heavy_module.h"
#include "cli/terminal_progress.h"

namespace {

const char* kUsage =
    "usage:\n"
    "  frepcad export MODEL.json|DOC.FCStd -o OUT [--resolution R | --cells N] [--tolerance D]\n"
    "                 [--bbox x0 y0 z0 x1 y1 z1] [--format stl|stl-ascii|obj|ply|bms|3mf]\n"
    "                 [--force] [--quiet] [--object NAME] [--set Object.Property=VALUE ...]\n"
    "                 (OUT.vdb: an OpenVDB level set at the cell size instead of a mesh)\n"
    "  frepcad deform IN.stl|IN.vdb --lattice LATTICE.json -o OUT [--force] [--quiet]\n"
    "  frepcad check MESH [--json] [--print [--min-wall MM] [--material NAME | --density D]\n"
    "                 [--up x|y|z|-x|-y|-z] [--overhang DEG]]\n"
    "  frepcad repair IN -o OUT [--rebuild auto|never|always] [--voxel V] [--force] [--json]\n"
    "  frepcad compare A B [--json]\n"
    "  frepcad info [TYPE | FILE.vdb] [--json | --markdown]\n"
    "  frepcad hspline new|info|refine|move|zero|unrefine|export ...   (hierarchical B-splines)\n"
    "  frepcad COMMAND --help   the options of one command\n"
    "  frepcad --version\n"
    "exit status: 0 ok, 1 mesh not printable, 2 bad input, 3 internal error,\n"
    "130 cancelled (Ctrl-C)\n";

}  // namespace

namespace frep::cli {
double parseNumber(const std::string& text, const std::string& option) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size()) return v;
  } catch (...) {
  }
  throw UsageError(option + " expects a number, got '" + text + "'");
}
}  // namespace frep::cli

int main(int argc, char** argv) {
  using namespace frep::cli;
  frep::useLargePageHeap();
  // A closed pipe on stdout makes writes fail (reported below), not kill the process.
  std::signal(SIGPIPE, SIG_IGN);
  // Models may name mesh and OpenVDB files (mesh_sdf, vdb_grid nodes): the first that does
  // loads the module that reads them.
  registerLazyVolumeSources();
  Args args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
    std::cout << kUsage;
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  // A report that cannot be written (a full disk or a closed pipe on stdout) is a failure,
  // not a silent exit 0.
  auto finish = [](int rc) {
    std::cout.flush();
    if (!std::cout) {
      std::cerr << "frepcad: cannot write the report to standard output (disk full or closed)\n";
      return rc == 0 ? 2 : rc;
    }
    return rc;
  };
  try {
    if (command == "export") return finish(exportCommand(args));
    if (command == "check") return finish(checkCommand(args));
    if (command == "info") return finish(infoCommand(args));
    // (in the module that links OpenVDB and OpenCASCADE, loaded now)
    if (command == "deform") return finish(heavyModule().deform(args));
    if (command == "repair") return finish(heavyModule().repair(args));
    if (command == "compare") return finish(heavyModule().compare(args));
    if (command == "hspline") return finish(heavyModule().hspline(args));
    // (not for users: a parent frepcad's read of an untrusted .vdb, cli/vdb_precheck.h)
    if (command == "__read-vdb" && args.size() == 1) return heavyModule().readVdbAlone(args[0]);
    if (command == "--version") {
      std::cout << "frepcad " FREPCAD_VERSION "\n";
      return 0;
    }
    throw UsageError("unknown command '" + command +
                     "'; commands: export, deform, check, repair, compare, info, hspline");
  } catch (const UsageError& e) {
    std::cerr << "frepcad: " << frep::shortenedLongWords(e.what()) << "\n" << kUsage;
    return frep::exitStatus(frep::Outcome::BadInput);
  } catch (...) {
    std::string line;
    const frep::Outcome outcome = frep::outcomeOf(std::current_exception(), &line);
    std::cerr << "frepcad: " << line << "\n";
    return frep::exitStatus(outcome);
  }
}

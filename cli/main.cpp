// frepcad: export FRep models to checked meshes, check mesh files, list node types.
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "frep/errors.h"

namespace {

const char* kUsage =
    "usage:\n"
    "  frepcad export MODEL.json -o OUT [--resolution R] [--bbox x0 y0 z0 x1 y1 z1]\n"
    "                 [--format stl|stl-ascii|obj|ply|bms] [--force] [--quiet]\n"
    "  frepcad export DOC.FCStd -o OUT [--object NAME] [--set Object.Property=VALUE ...]\n"
    "                 [--set Sheet.Alias=VALUE ...] [--cells N | --resolution R] [--quiet]\n"
    "  frepcad check MESH [--json]\n"
    "  frepcad info [TYPE] [--json | --markdown]\n"
    "exit status: 0 ok, 1 mesh not printable, 2 bad input\n";

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
  Args args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
    std::cout << kUsage;
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  try {
    if (command == "export") return exportCommand(args);
    if (command == "check") return checkCommand(args);
    if (command == "info") return infoCommand(args);
    if (command == "--version") {
      std::cout << "frepcad 0.1.0\n";
      return 0;
    }
    throw UsageError("unknown command '" + command + "'; commands: export, check, info");
  } catch (const UsageError& e) {
    std::cerr << "frepcad: " << e.what() << "\n" << kUsage;
  } catch (const frep::ModelError& e) {
    std::cerr << "frepcad: " << e.what() << "\n";
  } catch (const frep::FileError& e) {
    std::cerr << "frepcad: " << e.what() << "\n";
  } catch (const frep::Cancelled&) {
    std::cerr << "frepcad: cancelled; nothing written\n";
  } catch (const std::bad_alloc&) {
    std::cerr << "frepcad: out of memory; try a larger --resolution (cell size)\n";
  } catch (const std::exception& e) {
    std::cerr << "frepcad: " << e.what() << "\n";
  }
  return 2;
}

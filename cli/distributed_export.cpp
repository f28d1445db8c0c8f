// `frepcad export MODEL.json -o OUT --bricks N [--scheduler ADDRESS]`: the box is chosen
// here, as for any export; the jobs, the merge, the check and the write are
// frepcore.distributed's (Dask is Python's), run as `python3 -m frepcore.distributed` with the
// options in FREPCAD_EXPORT_ARGS. Its output, progress and exit status pass through.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/errors.h"
#include "cli/commands.h"
#include "cli/mesh_settings_flags.h"
#include "cli/terminal_progress.h"

extern char** environ;

namespace frep::cli {

int exportDistributed(const ExportOptions& o, const Box3& box, double resolution,
                      const std::vector<std::pair<std::string, std::string>>& metadata) {
  bool installed = false;
  const std::filesystem::path workbench = workbenchDir(&installed);
  // An installed workbench holds frepcore; the source tree's is in the build folder.
  const char* given = std::getenv("FREPCORE_PATH");
  const std::string frepcorePath = given && *given ? given
                                   : installed     ? workbench.string()
                                                   : FREPCORE_BUILD_DIR;
  const char* python = std::getenv("FREPCAD_PYTHON");
  const std::string interpreter = python && *python ? python : FREP_PYTHON;

  nlohmann::json args = {
      {"model", std::filesystem::absolute(o.input).string()},
      {"output", o.output},
      {"bricks", *o.bricks},
      {"bbox", {box.lo[0], box.lo[1], box.lo[2], box.hi[0], box.hi[1], box.hi[2]}},
      {"resolution", resolution},
      {"settings", nlohmann::json::parse(meshSettingsJson(o.mesh, {}))},
      {"format", o.format},
      {"units", o.units},
      {"metadata", metadata},
      {"force", o.force},
      {"quiet", o.quiet},
      {"scheduler", o.scheduler.empty() ? nullptr : nlohmann::json(o.scheduler)},
      {"work_dir", o.workDir.empty() ? nullptr : nlohmann::json(o.workDir)}};
  setenv("FREPCAD_EXPORT_ARGS", args.dump().c_str(), 1);
  const char* old = std::getenv("PYTHONPATH");
  setenv("PYTHONPATH", (frepcorePath + (old && *old ? ":" + std::string(old) : "")).c_str(), 1);

  std::vector<std::string> words = {interpreter, "-m", "frepcore.distributed"};
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  pid_t pid = 0;
  int status = 0;
  const int err = posix_spawnp(&pid, interpreter.c_str(), nullptr, nullptr, argv.data(), environ);
  if (err != 0)
    throw FileError("frepcad: cannot run " + interpreter + " for --bricks (set FREPCAD_PYTHON)");
  // Ctrl-C reaches the child too (one process group); a SIGTERM to us is passed on, and the
  // child cancels its jobs and removes its pieces.
  status = waitPassingOnInterrupts(pid);
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (interrupted()) return kExitCancelled;
  throw FileError("frepcad: the brick run's Python process stopped abnormally");
}

}  // namespace frep::cli

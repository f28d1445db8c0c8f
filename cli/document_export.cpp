// `frepcad export part.FCStd ...`: FRep documents are exported by FreeCAD itself, headless,
// running the workbench's FRepDocumentExport.py (which opens the document, applies --set
// overrides, recomputes and exports with the check). FreeCAD only loads FeaturePython classes
// from its Mod folders and its command-line value options crash on Debian's 0.20, so the
// workbench is linked into a private, temporary FreeCAD home and the arguments travel in an
// environment variable.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "base/errors.h"
#include "cli/commands.h"
#include "cli/mesh_settings_flags.h"
#include "cli/terminal_progress.h"

extern char** environ;

namespace frep::cli {

namespace fs = std::filesystem;

namespace {

std::string envOr(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : fallback;
}

// The options travel to Python as JSON text, which holds Unicode only: bytes that are not
// UTF-8 (a Latin-1 value typed into --set) are refused here, naming the option.
void requireUtf8(const std::string& text, const std::string& what) {
  try {
    (void)nlohmann::json(text).dump();
  } catch (const nlohmann::json::type_error&) {
    const std::string quoted = nlohmann::json(text.substr(0, 80))
                                   .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    throw ModelError(what + " " + quoted +
                     " is not UTF-8 text; FreeCAD documents take Unicode values and paths");
  }
}

// The private FreeCAD home, removed however the export ends.
struct TemporaryHome {
  fs::path path;
  ~TemporaryHome() {
    std::error_code ignored;
    if (!path.empty()) fs::remove_all(path, ignored);
  }
};

}  // namespace

int waitPassingOnInterrupts(pid_t pid) {
  // Ctrl-C and SIGTERM reach us (the handler only sets a flag): pass a SIGTERM on to the
  // child, which cancels and cleans up, and wait for it.
  installInterruptHandlers();
  bool forwarded = false;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) break;
    if (interrupted() && !forwarded) {
      kill(pid, SIGTERM);
      forwarded = true;
    }
  }
  return status;
}

bool isDocumentPath(const std::string& path) {
  if (path.size() < 6) return false;
  std::string ext = path.substr(path.size() - 6);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".fcstd";
}

// The workbench: FREPCAD_WORKBENCH_DIR, else the installed one beside this binary
// (<prefix>/bin/frepcad -> <prefix>/<FREP_MOD_DIR>/FRep), else the source tree's.
fs::path workbenchDir(bool* installed) {
  *installed = false;
  if (const char* v = std::getenv("FREPCAD_WORKBENCH_DIR"); v && *v) return v;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path beside = exe.parent_path() / FREP_INSTALLED_WORKBENCH;
    if (fs::exists(beside / "FRepDocumentExport.py", ec)) {
      *installed = true;
      return fs::weakly_canonical(beside, ec);
    }
  }
  return FREP_WORKBENCH_DIR;
}

int exportDocument(const ExportOptions& o) {
  bool installed = false;
  const fs::path workbench = workbenchDir(&installed);
  const fs::path script = workbench / "FRepDocumentExport.py";
  if (!fs::exists(script))
    throw FileError("frepcad: the FRep workbench is not at " + workbench.string() +
                    " (set FREPCAD_WORKBENCH_DIR)");
  const std::string freecadcmd = envOr("FREPCAD_FREECADCMD", "freecadcmd");

  requireUtf8(o.input, "the document");
  requireUtf8(o.output, "the output");
  for (const std::string& s : o.sets) requireUtf8(s, "--set");
  for (const std::string& s : o.objects) requireUtf8(s, "--object");

  std::string pattern = (fs::temp_directory_path() / "frepcad-home-XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw FileError("frepcad: cannot create a temporary folder");
  const TemporaryHome temporary{pattern};
  const fs::path& home = temporary.path;
  fs::create_directories(home / "Mod");
  fs::create_directory_symlink(fs::absolute(workbench), home / "Mod" / "FRep");

  setenv("FREECAD_USER_HOME", home.c_str(), 1);
  // An installed workbench carries its own frepcore; the source tree's is in the build.
  if (!installed) setenv("FREPCORE_PATH", envOr("FREPCORE_PATH", FREPCORE_BUILD_DIR).c_str(), 1);
  // The options travel parsed, so both kinds of input read them alike.
  nlohmann::json args = {
      {"document", o.input},
      {"output", o.output},
      {"format", o.format},
      {"objects", o.objects},
      {"sets", o.sets},
      {"force", o.force},
      {"quiet", o.quiet},
      {"cells", nullptr},
      {"resolution", nullptr},
      {"bbox", nullptr},
      {"units", o.units},
      // only the settings given: none leaves a mesh that is the part itself as it is
      {"settings", o.meshGiven.empty()
                       ? nlohmann::json::object()
                       : nlohmann::json::parse(meshSettingsJson(o.mesh, o.meshGiven))}};
  if (o.cells) args["cells"] = *o.cells;
  if (o.resolution) args["resolution"] = *o.resolution;
  if (o.bbox)
    args["bbox"] = {o.bbox->lo[0], o.bbox->lo[1], o.bbox->lo[2],
                    o.bbox->hi[0], o.bbox->hi[1], o.bbox->hi[2]};
  setenv("FREPCAD_EXPORT_ARGS", args.dump().c_str(), 1);

  std::string scriptText = script.string();
  std::vector<char*> argv = {const_cast<char*>(freecadcmd.c_str()), scriptText.data(), nullptr};
  // FreeCAD prints its banner and console progress on stdout: the child's stdout goes to
  // /dev/null and the script writes its report to fd 3, our stdout.
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, 3);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  std::fflush(stdout);
  pid_t pid = 0;
  int status = 0;
  const int err = posix_spawnp(&pid, freecadcmd.c_str(), &files, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  // (FreeCAD's export script cancels on a SIGTERM and removes its temporary file)
  if (err == 0) status = waitPassingOnInterrupts(pid);
  if (err != 0)
    throw FileError("frepcad: cannot run " + freecadcmd +
                    " (install FreeCAD: apt-get install "
                    "freecad freecad-python3)");
  if (interrupted()) return kExitCancelled;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  throw FileError("frepcad: FreeCAD stopped abnormally while exporting the document");
}

}  // namespace frep::cli

// The frepcad subcommands. Each returns the process exit code: 0 success, 1 the mesh is not
// printable (export refused, check failed), 2 bad input (usage, unreadable or invalid file),
// 3 internal error (a bug), 130 cancelled (SIGINT, SIGTERM).
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "base/vec.h"
#include "mesh/mesh_settings.h"

namespace frep::cli {

using Args = std::vector<std::string>;

// The options of `frepcad export`, the same for JSON models and FreeCAD documents.
struct ExportOptions {
  std::string input, output, format;
  std::vector<std::string> objects;  // --object NAME (repeatable; documents only)
  std::string units;                 // --units U: a 3MF's unit
  std::optional<double> resolution;
  std::optional<int> cells;
  std::optional<Box3> bbox;
  // The meshing flags (cli/mesh_settings_flags.h), and the table names of those given: a
  // document's Polygonize features take only those given over their own properties.
  MeshSettings mesh;
  std::set<std::string> meshGiven;
  bool stats = false;             // --stats: the accuracy report
  bool fog = false;               // --fog: a .vdb fog volume instead of a level set
  bool beams = false;             // --beams: a strut lattice as a 3MF beam lattice
  std::vector<std::string> sets;  // --set Object.Property=VALUE (documents only)
  bool force = false, quiet = false, help = false;
  // --bricks N: the export as N brick jobs on Dask (frepcore.distributed), on the scheduler
  // at --scheduler ADDRESS or a LocalCluster; piece files in --work-dir DIR
  std::optional<int> bricks;
  std::string scheduler, workDir;
};
// (its meshing flags are spelled from the table where %MESHING% stands)
extern const char* const kExportHelp;

int exportCommand(const Args& args);
int checkCommand(const Args& args);
int infoCommand(const Args& args);
int deformCommand(const Args& args);
int repairCommand(const Args& args);
int compareCommand(const Args& args);
int hsplineCommand(const Args& args);
// Refuses an output that is a link, a folder, a device or the input itself (FileError).
void checkOutputPath(const std::string& output, const std::string& input);
// `export DOC.FCStd ...`: runs the export inside FreeCAD, headless (document_export.cpp).
bool isDocumentPath(const std::string& path);
int exportDocument(const ExportOptions& options);
// Waits for a child process, passing a Ctrl-C or SIGTERM on to it as a SIGTERM; its wait
// status.
int waitPassingOnInterrupts(pid_t pid);
// The workbench folder (with frepcore inside it when installed; *installed says so), else
// the source tree's (frepcore then in the build).
std::filesystem::path workbenchDir(bool* installed);
// `export MODEL.json --bricks N`: the box chosen here, the run by frepcore.distributed in a
// Python child (distributed_export.cpp); `metadata` goes into a 3MF.
int exportDistributed(const ExportOptions& options, const Box3& box, double resolution,
                      const std::vector<std::pair<std::string, std::string>>& metadata);

// Thrown for a usage error: main prints it as one line and exits 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

double parseNumber(const std::string& text, const std::string& option);

}  // namespace frep::cli

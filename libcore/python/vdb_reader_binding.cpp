// frepcore has frepcad read each .vdb before OpenVDB reads it in this process, which may be
// FreeCAD: a damaged file then costs a one-line OSError, not FreeCAD itself
// (volume/vdb_reader_child.h).
#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "python/bindings.h"
#include "volume/grid_set.h"
#include "volume/vdb_reader_child.h"

namespace frep {

namespace {

bool isExecutable(const std::string& path) {
  return !path.empty() && access(path.c_str(), X_OK) == 0;
}

// The frepcad that came with this module: FREPCAD_EXECUTABLE when set; the build tree's when
// this module is the build tree's; PREFIX/bin/frepcad when this module is installed in
// PREFIX/FREPCORE_INSTALL_DIR; else the one the build would install. Never one found in PATH,
// which may be another version.
std::string findVdbReader() {
  if (const char* named = std::getenv("FREPCAD_EXECUTABLE"); named && *named) return named;
  Dl_info self{};
  const std::filesystem::path module =
      dladdr(reinterpret_cast<void*>(&findVdbReader), &self) && self.dli_fname ? self.dli_fname
                                                                               : "";
  const std::string folder = module.parent_path().lexically_normal().string();
  const std::string buildDir = FREPCAD_BUILD_DIR;
  if (folder.rfind(buildDir + "/", 0) == 0)
    return isExecutable(FREPCAD_BUILD_EXE) ? FREPCAD_BUILD_EXE : "";
  const std::string installDir = std::string("/") + FREPCORE_INSTALL_DIR;
  if (folder.size() > installDir.size() &&
      folder.compare(folder.size() - installDir.size(), installDir.size(), installDir) == 0) {
    const std::string installed =
        folder.substr(0, folder.size() - installDir.size()) + "/bin/frepcad";
    if (isExecutable(installed)) return installed;
  }
  return isExecutable(FREPCAD_INSTALLED_EXE) ? FREPCAD_INSTALLED_EXE : "";
}

}  // namespace

void bindVdbReader(pybind11::module_& m) {
  static const std::string reader = findVdbReader();
  if (!reader.empty())
    setVdbPrecheck([](const std::string& path) { readVdbInHelper(reader, path, {}); });
  m.def(
      "vdb_reader",
      []() -> pybind11::object {
        if (reader.empty()) return pybind11::none();
        return pybind11::str(reader);
      },
      "The frepcad that reads each .vdb file before this process does, so that a damaged file "
      "raises OSError instead of crashing the process (None: none was found, and OpenVDB reads "
      "files here directly). FREPCAD_EXECUTABLE names another.");
}

}  // namespace frep

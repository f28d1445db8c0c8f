// Finding and loading libfrepcad_heavy.so (heavy_module.h says why it is apart).
#include "cli/heavy_module.h"

#include <dlfcn.h>
#include <unistd.h>

#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "base/errors.h"
#include "frep/field_sources.h"

namespace frep::cli {

namespace {

namespace fs = std::filesystem;

const HeavyModule* load() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path dir = ec ? fs::path(".") : exe.parent_path();
  const std::vector<fs::path> candidates = {dir / "libfrepcad_heavy.so",
                                            dir / ".." / "lib" / "frepcad" / "libfrepcad_heavy.so"};
  std::string why;
  for (const fs::path& path : candidates) {
    if (!fs::exists(path, ec)) continue;
    // RTLD_NOW: a missing symbol is reported here, not as a crash in the middle of a command.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* e = dlerror();
      why = e ? e : "dlopen failed";
      continue;
    }
    using Entry = const HeavyModule* (*)();
    auto entry = reinterpret_cast<Entry>(dlsym(handle, "frepcad_heavy_module"));
    const HeavyModule* m = entry ? entry() : nullptr;
    if (!m || m->version != kHeavyModuleVersion) {
      why = path.string() + " is from another build of frepcad";
      continue;
    }
    return m;
  }
  throw FileError("cannot load frepcad's OpenVDB and OpenCASCADE module (" +
                  (why.empty() ? "libfrepcad_heavy.so is neither in " + dir.string() + " nor in " +
                                     (dir / ".." / "lib" / "frepcad").string()
                               : why) +
                  "): reinstall frepcad");
}

}  // namespace

const HeavyModule& heavyModule() {
  static std::once_flag once;
  static const HeavyModule* module = nullptr;
  std::call_once(once, [] { module = load(); });
  return *module;
}

void registerLazyVolumeSources() {
  for (const char* type : {"mesh_sdf", "vdb_grid", "voronoi_foam"})
    setFieldSourceLoader(type, [](const Node& node) {
      heavyModule().registerVolumeSources();  // replaces these stand-ins
      return loadFieldSource(node);
    });
}

}  // namespace frep::cli

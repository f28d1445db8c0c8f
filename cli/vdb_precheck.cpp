#include "cli/vdb_precheck.h"

#include <filesystem>
#include <stdexcept>
#include <string>

#include "cli/terminal_progress.h"
#include "volume/grid_set.h"
#include "volume/vdb_reader_child.h"

namespace frep::cli {

void readVdbInChild(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find frepcad's own executable: " + ec.message());
  readVdbInHelper(self.string(), path, [] { return interrupted(); });
}

int readVdbAlone(const std::string& path) {
  setVdbPrecheck(nullptr);
  readVdb(path);
  return 0;
}

}  // namespace frep::cli

#include "volume/vdb_reader_child.h"

#include <filesystem>
#include <string>

#include "base/child_process.h"
#include "base/errors.h"
#include "base/file_names.h"

namespace frep {

void readVdbInHelper(const std::string& helper, const std::string& path,
                     const std::function<bool()>& cancelled) {
  const std::string name = displayName(path);
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  const double limit = 30.0 + (ec ? 0.0 : static_cast<double>(bytes) / 20e6);
  ChildResult r;
  try {
    r = runChild({helper, "__read-vdb", path}, limit, cancelled);
  } catch (const std::runtime_error& e) {
    throw FileError(name + ": the OpenVDB file could not be read: " + e.what());
  }
  if (r.cancelled) throw Cancelled();
  if (r.timedOut)
    throw FileError(name + ": reading the OpenVDB file took over " +
                    std::to_string(static_cast<int>(limit)) + " s: a damaged file?");
  if (r.exited && r.exitCode == 0) return;
  if (!r.exited) {
    // A Ctrl-C reaches the helper too (one process group); that is the user's cancel.
    if (cancelled && cancelled()) throw Cancelled();
    throw FileError(name +
                    ": the OpenVDB file is damaged: OpenVDB's reader crashed on it (signal " +
                    std::to_string(r.signal) + ")");
  }
  // The helper's one line, without its "frepcad: ".
  std::string line = r.errorOutput.substr(0, r.errorOutput.find('\n'));
  if (line.rfind("frepcad: ", 0) == 0) line = line.substr(9);
  if (line.empty()) line = name + ": the OpenVDB file could not be read";
  throw FileError(line);
}

}  // namespace frep

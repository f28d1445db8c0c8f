#include "base/file_names.h"

#include <sys/stat.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "base/errors.h"

namespace frep {

namespace {
// Length of the valid UTF-8 sequence starting at s[i], or 0.
std::size_t utf8Length(const std::string& s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  std::size_t n = c < 0x80           ? 1
                  : (c >> 5) == 0x6  ? 2
                  : (c >> 4) == 0xE  ? 3
                  : (c >> 3) == 0x1E ? 4
                                     : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) >> 6) != 0x2) return 0;
  if (n == 2 && c < 0xC2) return 0;  // overlong
  return n;
}
}  // namespace

std::string displayName(const std::string& path) {
  std::string out;
  for (std::size_t i = 0; i < path.size();) {
    const std::size_t n = utf8Length(path, i);
    if (n == 0 || (n == 1 && static_cast<unsigned char>(path[i]) < 0x20)) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", static_cast<unsigned char>(path[i]));
      out += hex;
      ++i;
    } else {
      out.append(path, i, n);
      i += n;
    }
  }
  return out;
}

void requireRegularFile(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw FileError(displayName(path) + ": cannot open " + what + ": " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw FileError(displayName(path) + ": is a folder, not " + what);
  if (!S_ISREG(st.st_mode))
    throw FileError(displayName(path) + ": is not a regular file (a FIFO, socket or device), not " +
                    what);
}

std::string readSmallFile(const std::string& path, const std::string& kind,
                          std::uint64_t maxBytes) {
  // A folder, a FIFO (which would block) or a device is refused before it is opened, and so
  // is a file too large to be what it should be.
  requireRegularFile(path, "the " + kind);
  struct stat st {};
  ::stat(path.c_str(), &st);
  if (static_cast<std::uint64_t>(st.st_size) > maxBytes)
    throw FileError(displayName(path) + ": " + std::to_string(st.st_size) +
                    " bytes is too large for a " + kind + "; at most " + std::to_string(maxBytes) +
                    " are read");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(displayName(path) + ": cannot open the " + kind);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string fileExtension(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const auto dot = name.find_last_of('.');
  // a leading dot names a hidden file, not an extension
  if (dot == std::string::npos || dot == 0) return "";
  std::string ext = name.substr(dot + 1);
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool isVdbPath(const std::string& path) {
  return fileExtension(path) == "vdb";
}

}  // namespace frep

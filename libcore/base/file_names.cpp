#include "base/file_names.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "base/errors.h"

namespace frep {

namespace {
// Length of the valid UTF-8 sequence starting at s[i], or 0.
std::size_t utf8Length(const std::string& s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
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

}  // namespace frep

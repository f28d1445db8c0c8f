#include "base/atomic_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>

#include "base/errors.h"

namespace frep {

namespace {
std::string folderOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
}
}  // namespace

AtomicFile::AtomicFile(const std::string& path) : path_(path) {
  const auto slash = path.find_last_of('/');
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  if (name.empty()) throw FileError(path + ": not a file name");
  // A short temporary name, whatever the length of the target's (a name near the 255-byte
  // limit must still be writable); still recognisable by its prefix.
  std::string pattern = folderOf(path) + "/.frep-tmp-XXXXXX";
  const int fd = mkstemp(pattern.data());
  if (fd < 0)
    throw FileError(path + ": cannot write in folder '" + folderOf(path) +
                    "': " + std::strerror(errno));
  temp_ = pattern;
  file_ = fdopen(fd, "wb");
  if (!file_) {
    ::close(fd);
    std::remove(temp_.c_str());
    throw FileError(path + ": cannot open for writing: " + std::strerror(errno));
  }
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_ && !temp_.empty()) std::remove(temp_.c_str());
}

void AtomicFile::write(const void* data, std::size_t bytes) {
  if (bytes && std::fwrite(data, 1, bytes, file_) != bytes)
    throw FileError(path_ + ": write failed: " + std::strerror(errno));
}

void AtomicFile::writeAt(std::size_t offset, const void* data, std::size_t bytes) {
  if (std::fseek(file_, static_cast<long>(offset), SEEK_SET) != 0 ||
      std::fwrite(data, 1, bytes, file_) != bytes || std::fseek(file_, 0, SEEK_END) != 0)
    throw FileError(path_ + ": write failed: " + std::strerror(errno));
}

void AtomicFile::print(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  const int n = std::vfprintf(file_, fmt, args);
  va_end(args);
  if (n < 0) throw FileError(path_ + ": write failed: " + std::strerror(errno));
}

void AtomicFile::commit() {
  // mkstemp makes the file private (0600); the finished file gets the mode any new file
  // would get (0666 less the umask).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fileno(file_), 0666 & ~mask);
  const bool ok = std::fflush(file_) == 0 && fsync(fileno(file_)) == 0;
  const int closeResult = std::fclose(file_);
  file_ = nullptr;
  if (!ok || closeResult != 0)
    throw FileError(path_ + ": write failed: " + std::strerror(errno));
  if (std::rename(temp_.c_str(), path_.c_str()) != 0)
    throw FileError(path_ + ": cannot replace the file: " + std::strerror(errno));
  committed_ = true;
}

}  // namespace frep

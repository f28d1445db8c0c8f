// A file written under a temporary name in the target folder and renamed over the target
// only on commit(): a failure, an exception or a cancel leaves neither a partial file nor
// the temporary behind.
#pragma once

#include <cstdio>
#include <string>

namespace frep {

class AtomicFile {
 public:
  explicit AtomicFile(const std::string& path);  // throws FileError
  ~AtomicFile();                                  // removes the temporary unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(const void* data, std::size_t bytes);  // throws FileError
  void print(const char* fmt, ...);                 // printf-style, throws FileError
  // Overwrites bytes already written at `offset` (a header whose counts are known only at
  // the end), then goes on writing at the end; throws FileError.
  void writeAt(std::size_t offset, const void* data, std::size_t bytes);
  void commit();                                    // flush, close, rename; throws FileError
  // For a library that writes files only by name (OpenVDB): it writes this path, then
  // commit() renames it over the target as usual.
  const std::string& temporaryPath() const { return temp_; }

 private:
  std::string path_, temp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

}  // namespace frep

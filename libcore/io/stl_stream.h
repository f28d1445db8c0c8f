// Binary STL written a triangle at a time (brick merges: the whole mesh never sits
// in memory): the same bytes writeMesh writes for the same triangles in the same order, the
// count patched into the header at the end. Into an uncommitted AtomicFile, whose commit
// (or not) the caller decides.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "base/atomic_file.h"
#include "base/triangle_mesh.h"

namespace frep {

class StlStreamWriter {
 public:
  explicit StlStreamWriter(const std::string& path);         // throws FileError
  void add(const Vec3f& a, const Vec3f& b, const Vec3f& c);  // throws FileError
  // Writes what is buffered and the count; the file stays uncommitted.
  std::unique_ptr<AtomicFile> finish();
  std::size_t triangles() const { return count_; }

 private:
  std::unique_ptr<AtomicFile> file_;
  std::vector<char> buffer_;
  std::size_t count_ = 0;
};

}  // namespace frep

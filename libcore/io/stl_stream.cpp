#include "io/stl_stream.h"

#include <cstring>

#include "base/errors.h"
#include "base/triangle_geometry.h"

namespace frep {

StlStreamWriter::StlStreamWriter(const std::string& path)
    : file_(std::make_unique<AtomicFile>(path)) {
  char header[80] = {};
  std::strncpy(header, "FRepCAD binary STL", sizeof(header));
  file_->write(header, 80);
  const std::uint32_t none = 0;
  file_->write(&none, 4);  // (the count, patched by finish)
  buffer_.reserve(50 * 4096);
}

void StlStreamWriter::add(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  float record[12];
  const Vec3f n = unitNormal(a, b, c);
  std::memcpy(record, n.data(), 12);
  std::memcpy(record + 3, a.data(), 12);
  std::memcpy(record + 6, b.data(), 12);
  std::memcpy(record + 9, c.data(), 12);
  const char* bytes = reinterpret_cast<const char*>(record);
  buffer_.insert(buffer_.end(), bytes, bytes + 48);
  buffer_.push_back(0);
  buffer_.push_back(0);
  if (buffer_.size() >= 50 * 4096) {
    file_->write(buffer_.data(), buffer_.size());
    buffer_.clear();
  }
  ++count_;
}

std::unique_ptr<AtomicFile> StlStreamWriter::finish() {
  if (count_ > 0xFFFFFFFFull) throw FileError("too many triangles for STL");
  file_->write(buffer_.data(), buffer_.size());
  buffer_.clear();
  const std::uint32_t n = static_cast<std::uint32_t>(count_);
  file_->writeAt(80, &n, 4);
  return std::move(file_);
}

}  // namespace frep

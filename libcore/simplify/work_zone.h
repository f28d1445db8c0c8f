// Where a pass of straightening works: the blocks of the meshing box within a margin of the
// faces near a crease (simplify/simplify.h, creaseCollapsesOnly). Faces whose box meets no
// block of the zone are loaded into no region: on the twist the flat and gently twisted sides,
// on the sphere everything. A change is taken only where its faces' boxes lie in the zone's
// blocks, so no face left out can meet a changed face: a point they shared would lie in a
// block of the zone that the left-out face's box meets, and such a face is loaded.
// (Block indices are one clamped floor per coordinate, monotone, so a point in a box has its
// block in the box's range of blocks; the proof needs nothing else of the rounding.)
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>

#include "base/vec.h"

namespace frep {
namespace simplifying {

class WorkZone {
 public:
  // The box's blocks, about `block` on a side (larger where the box would hold over 2^27).
  WorkZone(const Box3& box, double block) {
    double side = block;
    for (;;) {
      double count = 1.0;
      for (int a = 0; a < 3; ++a) count *= std::ceil((box.hi[a] - box.lo[a]) / side) + 2 * kPad + 1;
      if (count <= double(1u << 27)) break;
      side *= 1.26;
    }
    perBlock_ = 1.0 / side;
    std::size_t blocks = 1;
    for (int a = 0; a < 3; ++a) {
      origin_[a] = box.lo[a] - kPad * side;
      dim_[a] = static_cast<std::int64_t>(std::ceil((box.hi[a] - box.lo[a]) / side)) + 2 * kPad + 1;
      blocks *= static_cast<std::size_t>(dim_[a]);
    }
    words_ = (blocks + 63) / 64;
    bits_.reset(new std::atomic<std::uint64_t>[words_]);
    for (std::size_t w = 0; w < words_; ++w) bits_[w].store(0, std::memory_order_relaxed);
    side_ = side;
  }

  double blockSide() const { return side_; }

  // Every block the box [lo, hi] grown by `margin` meets joins the zone (thread-safe).
  void add(const float lo[3], const float hi[3], double margin) {
    std::int64_t a[3], b[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = index(double(lo[k]) - margin, k);
      b[k] = index(double(hi[k]) + margin, k);
    }
    for (std::int64_t z = a[2]; z <= b[2]; ++z)
      for (std::int64_t y = a[1]; y <= b[1]; ++y)
        for (std::int64_t x = a[0]; x <= b[0]; ++x) {
          const std::size_t i = at(x, y, z);
          const std::uint64_t bit = std::uint64_t(1) << (i % 64);
          if (!(bits_[i / 64].load(std::memory_order_relaxed) & bit))
            bits_[i / 64].fetch_or(bit, std::memory_order_relaxed);
        }
  }
  // Whether the box meets a block of the zone (read once every add() has returned).
  bool meets(const float lo[3], const float hi[3]) const { return scan(lo, hi, true); }
  // Whether every block the box meets is in the zone.
  bool covers(const float lo[3], const float hi[3]) const { return !scan(lo, hi, false); }

 private:
  static constexpr int kPad = 2;  // blocks beyond the box on each side (vertices off it)

  std::int64_t index(double v, int a) const {
    const double i = std::floor((v - origin_[a]) * perBlock_);
    return static_cast<std::int64_t>(std::clamp(i, 0.0, static_cast<double>(dim_[a] - 1)));
  }
  std::size_t at(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return static_cast<std::size_t>((z * dim_[1] + y) * dim_[0] + x);
  }
  bool marked(std::size_t i) const {
    return (bits_[i / 64].load(std::memory_order_relaxed) >> (i % 64)) & 1u;
  }
  // whether a block of the box is (want) or is not (!want) in the zone
  bool scan(const float lo[3], const float hi[3], bool want) const {
    std::int64_t a[3], b[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = index(lo[k], k);
      b[k] = index(hi[k], k);
    }
    for (std::int64_t z = a[2]; z <= b[2]; ++z)
      for (std::int64_t y = a[1]; y <= b[1]; ++y)
        for (std::int64_t x = a[0]; x <= b[0]; ++x)
          if (marked(at(x, y, z)) == want) return true;
    return false;
  }

  double origin_[3] = {0, 0, 0}, perBlock_ = 1.0, side_ = 1.0;
  std::int64_t dim_[3] = {1, 1, 1};
  std::size_t words_ = 0;
  std::unique_ptr<std::atomic<std::uint64_t>[]> bits_;
};

}  // namespace simplifying
}  // namespace frep

// Minimal fixed-size vector and box types shared across libcore's public interfaces.
#pragma once

#include <array>

namespace frep {

using Vec3 = std::array<double, 3>;
using Mat34 = std::array<double, 12>;  // row-major 3x4 affine matrix [R | t]

struct Box3 {
  Vec3 lo{0, 0, 0};
  Vec3 hi{0, 0, 0};
  bool valid() const { return lo[0] < hi[0] && lo[1] < hi[1] && lo[2] < hi[2]; }
};

}  // namespace frep

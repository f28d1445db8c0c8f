// Node builders the C++ tests share, so that every file spells a primitive one way: the
// parameters in frepcore's positional order for a sphere (radius, then centre).
#pragma once

#include "base/vec.h"
#include "frep/tree.h"

namespace frep::testing {

inline NodePtr sphere(double radius, Vec3 center = {0, 0, 0}) {
  return makeNode("sphere", {{"radius", realValue(radius)}, {"center", vec3Value(center)}}, {});
}

// A block from its low corner and its edge lengths.
inline NodePtr box(Vec3 corner, Vec3 size) {
  return makeNode("box", {{"corner", vec3Value(corner)}, {"size", vec3Value(size)}}, {});
}

}  // namespace frep::testing

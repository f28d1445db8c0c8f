// Random FRep trees for property tests: random primitives, transforms and operations, with
// some parameters snapped to a grid so that field values are exactly zero at grid points.
#pragma once

#include <random>
#include <string>

#include "frep/tree.h"

namespace frep::testing {

class RandomTrees {
 public:
  explicit RandomTrees(unsigned seed) : rng_(seed) {}

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  // A coordinate, sometimes snapped to multiples of 1/8 (grid-aligned surfaces).
  double coord(double lo, double hi) {
    const double v = uniform(lo, hi);
    return integer(0, 3) == 0 ? std::round(v * 8) / 8 : v;
  }
  Vec3 point(double r) { return {coord(-r, r), coord(-r, r), coord(-r, r)}; }
  Vec3 direction() {
    const int pick = integer(0, 4);
    if (pick < 3) {
      Vec3 d{0, 0, 0};
      d[pick] = 1;
      return d;
    }
    Vec3 d{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
    if (std::abs(d[0]) + std::abs(d[1]) + std::abs(d[2]) < 1e-3) d = {0, 0, 1};
    return d;
  }
  double alpha() { return integer(0, 2) == 0 ? 1.0 : uniform(-0.9, 1.0); }

  // A primitive with a bounded solid (no half-space, no infinite cylinder).
  NodePtr boundedPrimitive() {
    for (;;) {
      NodePtr p = primitive();
      if (p->type->id != "halfspace" && !(p->type->id == "cylinder" && p->real("length") == 0))
        return p;
    }
  }

  NodePtr primitive() {
    switch (integer(0, 6)) {
      case 0:
        return makeNode("sphere", {{"center", vec3Value(point(0.8))}, {"radius", realValue(coord(0.15, 1.0) + 0.01)}}, {});
      case 1:
        return makeNode("box", {{"corner", vec3Value(point(1.0))},
                                {"size", vec3Value({coord(0.2, 1.4) + 0.01, coord(0.2, 1.4) + 0.01, coord(0.2, 1.4) + 0.01})}}, {});
      case 2:
        return makeNode("cylinder", {{"center", vec3Value(point(0.6))}, {"axis", vec3Value(direction())},
                                     {"radius", realValue(uniform(0.1, 0.6))},
                                     {"length", realValue(integer(0, 2) == 0 ? 0.0 : uniform(0.2, 2.0))}}, {});
      case 3:
        return makeNode("cone", {{"base", vec3Value(point(0.6))}, {"axis", vec3Value(direction())},
                                 {"radius1", realValue(uniform(0.1, 0.8))}, {"radius2", realValue(uniform(0.0, 0.5))},
                                 {"height", realValue(uniform(0.2, 1.5))}}, {});
      case 4:
        return makeNode("torus", {{"center", vec3Value(point(0.5))}, {"axis", vec3Value(direction())},
                                  {"major_radius", realValue(uniform(0.3, 0.8))},
                                  {"minor_radius", realValue(uniform(0.08, 0.3))}}, {});
      case 5:
        return makeNode("ellipsoid", {{"center", vec3Value(point(0.5))},
                                      {"radii", vec3Value({uniform(0.2, 1), uniform(0.2, 1), uniform(0.2, 1)})}}, {});
      default:
        return makeNode("halfspace", {{"point", vec3Value(point(0.5))}, {"normal", vec3Value(direction())}}, {});
    }
  }

  NodePtr tree(int depth) {
    if (depth <= 0 || integer(0, 3) == 0) return primitive();
    switch (integer(0, 9)) {
      case 0: return makeNode("translate", {{"offset", vec3Value(point(0.4))}}, {tree(depth - 1)});
      case 1:
        return makeNode("rotate", {{"axis", vec3Value(direction())}, {"angle", realValue(uniform(-180, 180))},
                                   {"center", vec3Value(point(0.3))}}, {tree(depth - 1)});
      case 2:
        return makeNode("scale", {{"factor", realValue(uniform(0.5, 1.5))},
                                  {"factors", vec3Value({uniform(0.6, 1.4), uniform(0.6, 1.4), uniform(0.6, 1.4)})}},
                        {tree(depth - 1)});
      case 3: return makeNode("complement", {}, {tree(depth - 1)});
      case 4: return makeNode("intersection", {{"alpha", realValue(alpha())}}, {tree(depth - 1), tree(depth - 1)});
      case 5: return makeNode("difference", {{"alpha", realValue(alpha())}}, {tree(depth - 1), tree(depth - 1)});
      case 6:
      case 7: return makeNode("blend_union", {{"a0", realValue(uniform(0.0, 0.6))}, {"a1", realValue(uniform(0.1, 1.0))},
                                              {"a2", realValue(uniform(0.1, 1.0))}, {"alpha", realValue(alpha())}},
                              {tree(depth - 1), tree(depth - 1)});
      case 8: return makeNode("blend_intersection", {{"a0", realValue(uniform(0.0, 0.4))}, {"a1", realValue(uniform(0.1, 1.0))},
                                                     {"a2", realValue(uniform(0.1, 1.0))}, {"alpha", realValue(alpha())}},
                              {tree(depth - 1), tree(depth - 1)});
      default: return makeNode("union", {{"alpha", realValue(alpha())}}, {tree(depth - 1), tree(depth - 1)});
    }
  }

  std::mt19937& engine() { return rng_; }

 private:
  std::mt19937 rng_;
};

}  // namespace frep::testing

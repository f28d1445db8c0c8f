// Quadric error functions: the sum of squared distances to a set of planes, and the point that
// minimises it (dual contouring's vertex placement; Garland and Heckbert's quadrics). Eigen
// stays in qef.cpp.
#pragma once

#include "base/vec.h"

namespace frep {

struct Quadric {
  double a[6] = {0, 0, 0, 0, 0, 0};  // symmetric A: xx, xy, xz, yy, yz, zz
  double b[3] = {0, 0, 0};
  double c = 0.0;
  Vec3 massSum{0, 0, 0};  // the planes' points, summed: their mean anchors the solution
  double count = 0.0;

  // The plane through p with unit normal n.
  void addPlane(const Vec3& p, const Vec3& n);
  Quadric& operator+=(const Quadric& q);
  // sum of squared distances of x to the planes
  double error(const Vec3& x) const;
  // The minimiser nearest the planes' mean point: directions whose eigenvalue is below
  // `relativeCutoff` of the largest are left at the mean (a flat region keeps its vertex on
  // the mean, a crease puts it on the crease line, a corner on the corner). The mean when
  // there are no planes. *rank (when given): the directions solved (1 a plane, 2 a crease
  // line, 3 a corner point).
  Vec3 minimiser(double relativeCutoff = 0.1, int* rank = nullptr) const;
  // False only where minimiser(relativeCutoff) would solve one direction at most (a plane):
  // a bound from the planes' normal matrix's trace T and principal minors M, whose second
  // eigenvalue over its largest is at most 9 M / T^2, without the eigen solve.
  bool mayBeSharp(double relativeCutoff) const;
};

}  // namespace frep

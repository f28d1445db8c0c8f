// A Sederberg-Parry free-form deformation lattice (seed 002): a rest box divided l x m x n
// times, (l+1)(m+1)(n+1) control points, and the trivariate Bernstein map from local
// coordinates (s, t, u) in [0, 1]^3 to space. Undeformed, the control points sit on the rest
// box's uniform grid and the map is the identity (Bernstein polynomials reproduce linear
// functions). The inverse map, solved by damped Newton steps from the trilinear inverse of
// the lattice's corners with a bracketing fallback, is what gap-free deformation of
// functions and grids needs: a point's value is the input's value at inverse(point).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "base/vec.h"

namespace frep {

using Mat3 = std::array<std::array<double, 3>, 3>;  // row r, column c: d x_r / d stu_c

// The Bernstein basis of degree d >= 1 at t and its derivative: b[i] = C(d,i) t^i (1-t)^(d-i),
// i = 0..d (both arrays d + 1 long).
void bernstein(int d, double t, double* b, double* db);

// At most this many divisions along an axis (Blender allows 64 points an axis; the issue asks
// for at least 64 divisions).
constexpr int kMaxLatticeDivisions = 64;

class FfdLattice {
 public:
  // The undeformed lattice over `rest` (every side > 0), divisions in [1, 64] per axis.
  // Throws ModelError naming the parameter and what is allowed.
  FfdLattice(const Box3& rest, int l, int m, int n);

  int divisions(int axis) const { return d_[axis]; }
  const Box3& rest() const { return rest_; }
  // Control point (i, j, k), 0 <= i <= l, ...
  const Vec3& point(int i, int j, int k) const { return p_[index(i, j, k)]; }
  void setPoint(int i, int j, int k, const Vec3& p);
  // Every control point in point()'s order: index i slowest, k fastest.
  const std::vector<Vec3>& points() const { return p_; }
  // All of them at once, in that order; throws ModelError for a wrong count or a point that
  // is not finite, naming it.
  void setPoints(const std::vector<Vec3>& points);
  std::size_t pointCount() const { return p_.size(); }
  // Every control point exactly at its rest position (the map is then the identity).
  bool isUndeformed() const;

  // rest space <-> local coordinates (affine).
  Vec3 local(const Vec3& x) const;
  Vec3 restPoint(const Vec3& stu) const;
  // The deformed point X(s, t, u) and its Jacobian dX / d(s, t, u).
  Vec3 forward(const Vec3& stu) const;
  Vec3 forward(const Vec3& stu, Mat3* jacobian) const;
  // A rest-space point moved by the lattice (points outside the rest box do not move).
  Vec3 deform(const Vec3& x) const;
  // The local coordinates whose image is y, or nullopt when y is not the image of a point of
  // [0, 1]^3 (outside the deformed lattice) or the map is folded there.
  std::optional<Vec3> inverse(const Vec3& y) const;
  // Damped Newton steps from `start` towards X(s) = y: the local coordinates once the residual
  // is below 1e-10 of the rest box's largest side (they may lie outside [0, 1]^3), else
  // nullopt. The building block of inverse() and FfdMap::inverse().
  std::optional<Vec3> newton(const Vec3& y, const Vec3& start) const;
  // The largest side of the rest box (the scale of tolerances).
  double scale() const;

  // A box holding X(S) for the parameter box S (within [0, 1]^3; a side may be flat): the box
  // of the control points of the Bezier volume restricted to S (de Casteljau subdivision on
  // each axis), which hold its image in their convex hull, padded for rounding.
  Box3 imageBounds(const Box3& stu) const;
  // The control points of the Bezier volume restricted to S, in point() order.
  std::vector<Vec3> restrictedPoints(const Box3& stu) const;

  // Where the Jacobian's determinant changes sign (the lattice folds over itself), sampled
  // at `samples` points an axis in each lattice cell: the cell and a point there.
  struct Fold {
    int cell[3];
    Vec3 stu;
    std::string text() const;  // "the lattice folds in cell (2, 0, 1) near (s, t, u) = ..."
  };
  std::optional<Fold> findFold(int samples = 3) const;

 private:
  std::size_t index(int i, int j, int k) const {
    return (std::size_t(i) * (d_[1] + 1) + std::size_t(j)) * (d_[2] + 1) + std::size_t(k);
  }
  Box3 rest_;
  int d_[3];
  std::vector<Vec3> p_;
};

double determinant(const Mat3& m);
// The inverse of m by cofactors; false when m is singular (or not finite).
bool invert(const Mat3& m, Mat3* inverse);
// s lies in [0, 1]^3, give or take 1e-9 (what inverse() accepts as inside the lattice).
bool insideUnitCube(const Vec3& s);
// s lies within a quarter of the cube's side of [0, 1]^3: where a Newton solution outside the
// cube still says that its point is outside the deformed lattice (the map continued past the
// lattice takes a point there to it, so for a lattice that does not fold nothing inside does).
bool nearUnitCube(const Vec3& s);

}  // namespace frep

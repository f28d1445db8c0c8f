// Affine maps as row-major 3x4 matrices [R | t] (q = R p + t): the linear algebra the node
// types need, computed with Eigen (kept out of this header, so the many files that build
// programs do not compile Eigen's templates).
#pragma once

#include "base/vec.h"

namespace frep {

// The inverse map. Precondition: the linear part is invertible (the registry refuses a
// singular matrix parameter; see linearDeterminant).
Mat34 invertAffine(const Mat34& m);

// The determinant of the linear part R.
double linearDeterminant(const Mat34& m);

// Rotation by `angleDeg` degrees about `axis` (any length but zero) through `center`:
// q = R (p - c) + c.
Mat34 rotationMatrix(const Vec3& axis, double angleDeg, const Vec3& center);

// Whether the linear part is a rotation (orthonormal, determinant +1) within `tolerance`.
bool isRigid(const Mat34& m, double tolerance = 1e-6);

// Between two rigid maps: their rotations interpolated (slerp, t from 0 to 1) about `centre`,
// which goes to the point between where the two maps take it. An average of the two maps'
// images instead would shrink what it carries (a joint's inner side).
Mat34 rotationAbout(const Mat34& a, const Mat34& b, double t, const Vec3& centre);

// v / |v|.
Vec3 normalized(const Vec3& v);

// p x q.
Vec3 cross(const Vec3& p, const Vec3& q);

}  // namespace frep

#include "base/affine.h"

#include <Eigen/Geometry>
#include <cmath>

namespace frep {

namespace {
constexpr double kPi = 3.14159265358979323846;

using Affine = Eigen::Transform<double, 3, Eigen::Affine, Eigen::RowMajor>;

Affine toEigen(const Mat34& m) {
  Affine a;
  a.matrix().topRows<3>() =
      Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(m.data());
  a.matrix().row(3) << 0, 0, 0, 1;
  return a;
}

Mat34 fromEigen(const Affine& a) {
  Mat34 m{};
  Eigen::Map<Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(m.data()) = a.matrix().topRows<3>();
  return m;
}

Eigen::Vector3d toEigen(const Vec3& v) {
  return {v[0], v[1], v[2]};
}
Vec3 fromEigen(const Eigen::Vector3d& v) {
  return {v[0], v[1], v[2]};
}
}  // namespace

Mat34 invertAffine(const Mat34& m) {
  return fromEigen(toEigen(m).inverse(Eigen::Affine));
}

double linearDeterminant(const Mat34& m) {
  return toEigen(m).linear().determinant();
}

Mat34 rotationMatrix(const Vec3& axis, double angleDeg, const Vec3& center) {
  const Eigen::Vector3d c = toEigen(center);
  Affine a = Affine::Identity();
  a.translate(c)
      .rotate(Eigen::AngleAxisd(angleDeg * kPi / 180.0, toEigen(axis).normalized()))
      .translate(-c);
  return fromEigen(a);
}

Vec3 normalized(const Vec3& v) {
  return fromEigen(toEigen(v).normalized());
}

bool isRigid(const Mat34& m, double tolerance) {
  const Eigen::Matrix3d r = toEigen(m).linear();
  return (r.transpose() * r).isIdentity(tolerance) && r.determinant() > 0;
}

Mat34 rotationAbout(const Mat34& a, const Mat34& b, double t, const Vec3& centre) {
  const Eigen::Quaterniond qa(Eigen::Matrix3d(toEigen(a).linear()));
  const Eigen::Quaterniond qb(Eigen::Matrix3d(toEigen(b).linear()));
  const Eigen::Vector3d c = toEigen(centre);
  const Eigen::Vector3d target = (1 - t) * (toEigen(a) * c) + t * (toEigen(b) * c);
  Affine out = Affine::Identity();
  out.linear() = qa.slerp(t, qb).toRotationMatrix();
  out.translation() = target - out.linear() * c;
  return fromEigen(out);
}

Vec3 cross(const Vec3& p, const Vec3& q) {
  return fromEigen(toEigen(p).cross(toEigen(q)));
}

}  // namespace frep

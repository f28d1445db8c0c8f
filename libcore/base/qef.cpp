#include "base/qef.h"

#include <Eigen/Dense>
#include <cmath>

namespace frep {

void Quadric::addPlane(const Vec3& p, const Vec3& n) {
  const double d = n[0] * p[0] + n[1] * p[1] + n[2] * p[2];
  a[0] += n[0] * n[0];
  a[1] += n[0] * n[1];
  a[2] += n[0] * n[2];
  a[3] += n[1] * n[1];
  a[4] += n[1] * n[2];
  a[5] += n[2] * n[2];
  for (int k = 0; k < 3; ++k) {
    b[k] += n[k] * d;
    massSum[k] += p[k];
  }
  c += d * d;
  count += 1.0;
}

Quadric& Quadric::operator+=(const Quadric& q) {
  for (int k = 0; k < 6; ++k) a[k] += q.a[k];
  for (int k = 0; k < 3; ++k) {
    b[k] += q.b[k];
    massSum[k] += q.massSum[k];
  }
  c += q.c;
  count += q.count;
  return *this;
}

double Quadric::error(const Vec3& x) const {
  const double ax[3] = {a[0] * x[0] + a[1] * x[1] + a[2] * x[2],
                        a[1] * x[0] + a[3] * x[1] + a[4] * x[2],
                        a[2] * x[0] + a[4] * x[1] + a[5] * x[2]};
  const double e = x[0] * ax[0] + x[1] * ax[1] + x[2] * ax[2] -
                   2.0 * (b[0] * x[0] + b[1] * x[1] + b[2] * x[2]) + c;
  return e > 0.0 ? e : 0.0;  // rounding
}

bool Quadric::mayBeSharp(double relativeCutoff) const {
  if (count <= 0.0) return false;
  const double t = a[0] + a[3] + a[5];
  const double m =
      (a[0] * a[3] - a[1] * a[1]) + (a[0] * a[5] - a[2] * a[2]) + (a[3] * a[5] - a[4] * a[4]);
  // (with a margin, so that rounding never hides a direction the solve would count)
  return !(t > 0.0) || 9.0 * m > 0.5 * relativeCutoff * t * t;
}

Vec3 Quadric::minimiser(double relativeCutoff, int* rank) const {
  if (rank) *rank = 0;
  if (count <= 0.0) return {0, 0, 0};
  const Eigen::Vector3d m(massSum[0] / count, massSum[1] / count, massSum[2] / count);
  Eigen::Matrix3d A;
  A << a[0], a[1], a[2], a[1], a[3], a[4], a[2], a[4], a[5];
  const Eigen::Vector3d r = Eigen::Vector3d(b[0], b[1], b[2]) - A * m;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
  const Eigen::Vector3d lambda = eig.eigenvalues();
  const double largest = lambda.cwiseAbs().maxCoeff();
  Eigen::Vector3d x = m;
  if (largest > 0.0)
    for (int k = 0; k < 3; ++k)
      if (std::abs(lambda[k]) > relativeCutoff * largest) {
        const Eigen::Vector3d e = eig.eigenvectors().col(k);
        x += e * (e.dot(r) / lambda[k]);
        if (rank) ++*rank;
      }
  return {x[0], x[1], x[2]};
}

}  // namespace frep

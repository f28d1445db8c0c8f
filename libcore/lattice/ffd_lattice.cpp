// FfdLattice: Bernstein evaluation by the triangular (de Casteljau style) scheme, stable at 64
// divisions where binomial coefficients and powers lose precision.
#include "lattice/ffd_lattice.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <vector>

#include "base/errors.h"

namespace frep {

void bernstein(int d, double t, double* b, double* db) {
  // Degree d-1 first (for the derivative), then one more step.
  std::fill(b, b + d + 1, 0.0);
  b[0] = 1.0;
  const double s = 1.0 - t;
  for (int deg = 1; deg < d; ++deg) {
    for (int i = deg; i > 0; --i) b[i] = s * b[i] + t * b[i - 1];
    b[0] *= s;
  }
  // b holds degree d-1 now: the derivative is d (B_{i-1}^{d-1} - B_i^{d-1}).
  for (int i = 0; i <= d; ++i) {
    const double left = i > 0 ? b[i - 1] : 0.0, right = i < d ? b[i] : 0.0;
    db[i] = d * (left - right);
  }
  for (int i = d; i > 0; --i) b[i] = s * b[i] + t * b[i - 1];
  b[0] *= s;
}

namespace {

Vec3 solve(const Mat3& a, const Vec3& r, bool* ok) {
  const double det = determinant(a);
  *ok = std::isfinite(det) && std::abs(det) > 1e-300;
  if (!*ok) return {0, 0, 0};
  Vec3 x;
  for (int c = 0; c < 3; ++c) {
    Mat3 m = a;
    for (int row = 0; row < 3; ++row) m[row][c] = r[row];
    x[c] = determinant(m) / det;
  }
  return x;
}

double norm(const Vec3& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

// newton() accepts a residual up to this fraction of the lattice's scale.
constexpr double kInverseTolerance = 1e-10;

}  // namespace

double determinant(const Mat3& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

bool invert(const Mat3& m, Mat3* inv) {
  const double det = determinant(m);
  if (!std::isfinite(det) || std::abs(det) < 1e-300) return false;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      // cofactor of (c, r), the transposed position
      const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
      (*inv)[r][c] = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det;
    }
  return true;
}

FfdLattice::FfdLattice(const Box3& rest, int l, int m, int n) : rest_(rest), d_{l, m, n} {
  const char* names[3] = {"divisions x", "divisions y", "divisions z"};
  for (int a = 0; a < 3; ++a) {
    if (d_[a] < 1 || d_[a] > kMaxLatticeDivisions)
      throw ModelError("lattice: " + std::string(names[a]) + " = " + std::to_string(d_[a]) +
                       " is out of range; allowed: 1 to " + std::to_string(kMaxLatticeDivisions));
    if (!(rest.hi[a] > rest.lo[a]) || !std::isfinite(rest.lo[a]) || !std::isfinite(rest.hi[a]))
      throw ModelError("lattice: the rest box must be finite with min < max on every axis");
  }
  p_.resize(std::size_t(l + 1) * (m + 1) * (n + 1));
  for (int i = 0; i <= l; ++i)
    for (int j = 0; j <= m; ++j)
      for (int k = 0; k <= n; ++k)
        p_[index(i, j, k)] = restPoint({double(i) / l, double(j) / m, double(k) / n});
}

void FfdLattice::setPoint(int i, int j, int k, const Vec3& p) {
  if (i < 0 || j < 0 || k < 0 || i > d_[0] || j > d_[1] || k > d_[2])
    throw ModelError("lattice: control point (" + std::to_string(i) + ", " + std::to_string(j) +
                     ", " + std::to_string(k) + ") does not exist; allowed: (0..." +
                     std::to_string(d_[0]) + ", 0..." + std::to_string(d_[1]) + ", 0..." +
                     std::to_string(d_[2]) + ")");
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    throw ModelError("lattice: control point coordinates must be finite");
  p_[index(i, j, k)] = p;
}

void FfdLattice::setPoints(const std::vector<Vec3>& points) {
  if (points.size() != p_.size())
    throw ModelError("lattice: " + std::to_string(points.size()) + " points given; a " +
                     std::to_string(d_[0]) + " x " + std::to_string(d_[1]) + " x " +
                     std::to_string(d_[2]) + " lattice has " + std::to_string(p_.size()) +
                     " control points (i slowest, k fastest)");
  for (std::size_t n = 0; n < points.size(); ++n)
    if (!std::isfinite(points[n][0]) || !std::isfinite(points[n][1]) ||
        !std::isfinite(points[n][2]))
      throw ModelError("lattice: control point " + std::to_string(n) +
                       ": coordinates must be finite");
  p_ = points;
}

bool FfdLattice::isUndeformed() const {
  for (int i = 0; i <= d_[0]; ++i)
    for (int j = 0; j <= d_[1]; ++j)
      for (int k = 0; k <= d_[2]; ++k)
        if (p_[index(i, j, k)] !=
            restPoint({double(i) / d_[0], double(j) / d_[1], double(k) / d_[2]}))
          return false;
  return true;
}

Vec3 FfdLattice::local(const Vec3& x) const {
  Vec3 s;
  for (int a = 0; a < 3; ++a) s[a] = (x[a] - rest_.lo[a]) / (rest_.hi[a] - rest_.lo[a]);
  return s;
}

Vec3 FfdLattice::restPoint(const Vec3& stu) const {
  Vec3 x;
  for (int a = 0; a < 3; ++a) x[a] = rest_.lo[a] + stu[a] * (rest_.hi[a] - rest_.lo[a]);
  return x;
}

Vec3 FfdLattice::forward(const Vec3& stu) const {
  return forward(stu, nullptr);
}

Vec3 FfdLattice::forward(const Vec3& stu, Mat3* jacobian) const {
  double b[3][kMaxLatticeDivisions + 1], db[3][kMaxLatticeDivisions + 1];
  for (int a = 0; a < 3; ++a) bernstein(d_[a], stu[a], b[a], db[a]);
  // Summed along k first for each (i, j): the value's and the u-derivative's partial sums,
  // then weighted by the i and j factors (a third of the products of the plain triple sum).
  double x0 = 0, x1 = 0, x2 = 0;
  double j00 = 0, j10 = 0, j20 = 0, j01 = 0, j11 = 0, j21 = 0, j02 = 0, j12 = 0, j22 = 0;
  const std::size_t nk = std::size_t(d_[2]) + 1;
  for (int i = 0; i <= d_[0]; ++i)
    for (int j = 0; j <= d_[1]; ++j) {
      const Vec3* p = &p_[index(i, j, 0)];
      double s0 = 0, s1 = 0, s2 = 0, u0 = 0, u1 = 0, u2 = 0;
      if (jacobian) {
        for (std::size_t k = 0; k < nk; ++k) {
          const double w = b[2][k], dw = db[2][k];
          s0 += w * p[k][0], s1 += w * p[k][1], s2 += w * p[k][2];
          u0 += dw * p[k][0], u1 += dw * p[k][1], u2 += dw * p[k][2];
        }
      } else {
        for (std::size_t k = 0; k < nk; ++k) {
          const double w = b[2][k];
          s0 += w * p[k][0], s1 += w * p[k][1], s2 += w * p[k][2];
        }
      }
      const double bij = b[0][i] * b[1][j];
      x0 += bij * s0, x1 += bij * s1, x2 += bij * s2;
      if (jacobian) {
        const double ws = db[0][i] * b[1][j], wt = b[0][i] * db[1][j];
        j00 += ws * s0, j10 += ws * s1, j20 += ws * s2;
        j01 += wt * s0, j11 += wt * s1, j21 += wt * s2;
        j02 += bij * u0, j12 += bij * u1, j22 += bij * u2;
      }
    }
  if (jacobian) *jacobian = Mat3{{{j00, j01, j02}, {j10, j11, j12}, {j20, j21, j22}}};
  return {x0, x1, x2};
}

Vec3 FfdLattice::deform(const Vec3& x) const {
  const Vec3 s = local(x);
  for (int a = 0; a < 3; ++a)
    if (s[a] < 0.0 || s[a] > 1.0) return x;
  return forward(s);
}

double FfdLattice::scale() const {
  double scale = 0.0;
  for (int a = 0; a < 3; ++a) scale = std::max(scale, rest_.hi[a] - rest_.lo[a]);
  return scale;
}

std::optional<Vec3> FfdLattice::newton(const Vec3& y, const Vec3& start) const {
  const double tol = 1e-13 * scale();
  Vec3 s = start;
  Mat3 j;
  Vec3 x = forward(s, &j);
  double res = norm({x[0] - y[0], x[1] - y[1], x[2] - y[2]});
  // Each step halves until the residual shrinks (damping).
  for (int it = 0; it < 60 && res > tol; ++it) {
    bool ok = false;
    const Vec3 step = solve(j, {y[0] - x[0], y[1] - x[1], y[2] - x[2]}, &ok);
    if (!ok) return std::nullopt;
    double f = 1.0;
    bool better = false;
    for (int h = 0; h < 30; ++h, f *= 0.5) {
      const Vec3 t{s[0] + f * step[0], s[1] + f * step[1], s[2] + f * step[2]};
      Mat3 jt;
      const Vec3 xt = forward(t, &jt);
      const double rt = norm({xt[0] - y[0], xt[1] - y[1], xt[2] - y[2]});
      if (rt < res) {
        s = t, x = xt, j = jt, res = rt;
        better = true;
        break;
      }
    }
    if (!better) break;
  }
  if (!(res <= kInverseTolerance * scale())) return std::nullopt;
  return s;
}

bool insideUnitCube(const Vec3& s) {
  constexpr double eps = 1e-9;
  return s[0] >= -eps && s[0] <= 1 + eps && s[1] >= -eps && s[1] <= 1 + eps && s[2] >= -eps &&
         s[2] <= 1 + eps;
}

bool nearUnitCube(const Vec3& s) {
  return s[0] > -0.25 && s[0] < 1.25 && s[1] > -0.25 && s[1] < 1.25 && s[2] > -0.25 &&
         s[2] < 1.25;
}

std::optional<Vec3> FfdLattice::inverse(const Vec3& y) const {
  // First guess: the rest-space local coordinates of y (exact for the identity), then the
  // centre; last, a bracketing search over a grid of starts, nearest image first.
  std::vector<Vec3> starts = {local(y), {0.5, 0.5, 0.5}};
  for (const Vec3& s0 : starts) {
    Vec3 c{std::clamp(s0[0], 0.0, 1.0), std::clamp(s0[1], 0.0, 1.0), std::clamp(s0[2], 0.0, 1.0)};
    if (auto s = newton(y, c); s && insideUnitCube(*s)) return s;
  }
  constexpr int kGrid = 6;
  std::vector<std::pair<double, Vec3>> grid;
  for (int i = 0; i <= kGrid; ++i)
    for (int j = 0; j <= kGrid; ++j)
      for (int k = 0; k <= kGrid; ++k) {
        const Vec3 s{double(i) / kGrid, double(j) / kGrid, double(k) / kGrid};
        const Vec3 x = forward(s);
        grid.push_back({norm({x[0] - y[0], x[1] - y[1], x[2] - y[2]}), s});
      }
  std::stable_sort(grid.begin(), grid.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t g = 0; g < std::min<std::size_t>(grid.size(), 12); ++g)
    if (auto s = newton(y, grid[g].second); s && insideUnitCube(*s)) return s;
  return std::nullopt;
}

namespace {
// The control values of the Bezier curve c (degree d, d + 1 values, stride `stride`)
// restricted to [lo, hi] within [0, 1], in place: split at hi keeping the left part, then
// at lo / hi keeping the right part (de Casteljau).
void restrictCurve(Vec3* c, int d, std::size_t stride, double lo, double hi) {
  if (d < 1 || d > kMaxLatticeDivisions) return;
  Vec3 w[kMaxLatticeDivisions + 1], out[kMaxLatticeDivisions + 1];
  for (int i = 0; i <= d; ++i) w[i] = c[i * stride];
  if (hi <= 0.0) {
    for (int i = 0; i <= d; ++i) c[i * stride] = w[0];
    return;
  }
  auto lerp = [](const Vec3& a, const Vec3& b, double t) {
    return Vec3{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
  };
  if (hi < 1.0) {  // left part of the split at hi: the first value of every level
    out[0] = w[0];
    for (int r = 1; r <= d; ++r) {
      for (int i = 0; i <= d - r; ++i) w[i] = lerp(w[i], w[i + 1], hi);
      out[r] = w[0];
    }
    for (int i = 0; i <= d; ++i) w[i] = out[i];
  }
  const double t = lo / hi;
  if (t > 0.0) {  // right part of the split at t: the last value of every level
    out[d] = w[d];
    for (int r = 1; r <= d; ++r) {
      for (int i = 0; i <= d - r; ++i) w[i] = lerp(w[i], w[i + 1], t);
      out[d - r] = w[d - r];
    }
    for (int i = 0; i <= d; ++i) w[i] = out[i];
  }
  for (int i = 0; i <= d; ++i) c[i * stride] = w[i];
}
}  // namespace

std::vector<Vec3> FfdLattice::restrictedPoints(const Box3& stu) const {
  std::vector<Vec3> q = p_;
  const std::size_t strides[3] = {std::size_t(d_[1] + 1) * (d_[2] + 1), std::size_t(d_[2] + 1), 1};
  for (int a = 0; a < 3; ++a) {
    const double lo = std::clamp(stu.lo[a], 0.0, 1.0), hi = std::clamp(stu.hi[a], lo, 1.0);
    if (lo == 0.0 && hi == 1.0) continue;
    // every fiber along axis a: the index with its a-th coordinate 0
    for (int i = 0; i <= (a == 0 ? 0 : d_[0]); ++i)
      for (int j = 0; j <= (a == 1 ? 0 : d_[1]); ++j)
        for (int k = 0; k <= (a == 2 ? 0 : d_[2]); ++k)
          restrictCurve(&q[index(i, j, k)], d_[a], strides[a], lo, hi);
  }
  return q;
}

Box3 FfdLattice::imageBounds(const Box3& stu) const {
  const std::vector<Vec3> q = restrictedPoints(stu);
  Box3 b{q[0], q[0]};
  double reach = scale();
  for (const Vec3& v : q)
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min(b.lo[a], v[a]);
      b.hi[a] = std::max(b.hi[a], v[a]);
      reach = std::max(reach, std::abs(v[a]));
    }
  // Rounding in the subdivision and in forward() stays far below this; it also covers the
  // residual newton() accepts, so a point inverse() finds lies in its parameter box's bounds.
  const double pad = 1e-9 * reach;
  for (int a = 0; a < 3; ++a) b.lo[a] -= pad, b.hi[a] += pad;
  return b;
}

std::string FfdLattice::Fold::text() const {
  std::ostringstream o;
  o << "the lattice folds over itself in cell (" << cell[0] << ", " << cell[1] << ", " << cell[2]
    << ") near (s, t, u) = (" << stu[0] << ", " << stu[1] << ", " << stu[2]
    << "): move its control points apart";
  return o.str();
}

// The Jacobian at every sample of every cell (`samples` per cell and axis, at the centres of
// a regular grid), by separable sums: contracted along k, then j, then i. Evaluated point by
// point, each sample would cost every control point, 274,625 of them at 64 divisions, and
// the 7 million samples hours; the separable sums cost seconds. The first fold in the order
// cell by cell, then sample by sample, is reported, as a scan point by point would.
std::optional<FfdLattice::Fold> FfdLattice::findFold(int samples) const {
  samples = std::max(samples, 1);
  const int d0 = d_[0], d1 = d_[1], d2 = d_[2];
  const int n0 = d0 * samples, n1 = d1 * samples, n2 = d2 * samples;
  auto table = [samples](int d, int n, std::vector<double>& b, std::vector<double>& db) {
    b.assign(std::size_t(n) * (d + 1), 0.0);
    db.assign(b.size(), 0.0);
    for (int m = 0; m < n; ++m) {
      const int cell = m / samples, within = m % samples;
      const double t = (cell + (within + 0.5) / samples) / d;
      bernstein(d, t, &b[std::size_t(m) * (d + 1)], &db[std::size_t(m) * (d + 1)]);
    }
  };
  std::vector<double> b0, db0, b1, db1, b2, db2;
  table(d0, n0, b0, db0);
  table(d1, n1, b1, db1);
  table(d2, n2, b2, db2);
  // Along k: a[(i, j, w)] = sum_k B_k(w) P_ijk and its u-derivative.
  const std::size_t ij = std::size_t(d0 + 1) * (d1 + 1);
  std::vector<Vec3> a(ij * n2), au(ij * n2);
  for (std::size_t row = 0; row < ij; ++row) {
    const Vec3* p = &p_[row * (d2 + 1)];
    for (int w = 0; w < n2; ++w) {
      const double* bw = &b2[std::size_t(w) * (d2 + 1)];
      const double* dbw = &db2[std::size_t(w) * (d2 + 1)];
      Vec3 v{0, 0, 0}, u{0, 0, 0};
      for (int k = 0; k <= d2; ++k)
        for (int c = 0; c < 3; ++c) {
          v[c] += bw[k] * p[k][c];
          u[c] += dbw[k] * p[k][c];
        }
      a[row * n2 + w] = v;
      au[row * n2 + w] = u;
    }
  }
  std::vector<std::int8_t> signs(std::size_t(n0) * n1 * n2);
  std::vector<Vec3> value(std::size_t(d0 + 1) * n2), dt(value.size()), du(value.size());
  for (int v = 0; v < n1; ++v) {
    // Along j, for this t sample: the value and its t- and u-derivatives per (i, w).
    const double* bv = &b1[std::size_t(v) * (d1 + 1)];
    const double* dbv = &db1[std::size_t(v) * (d1 + 1)];
    for (int i = 0; i <= d0; ++i)
      for (int w = 0; w < n2; ++w) {
        Vec3 x{0, 0, 0}, xt{0, 0, 0}, xu{0, 0, 0};
        for (int j = 0; j <= d1; ++j) {
          const std::size_t at = (std::size_t(i) * (d1 + 1) + j) * n2 + w;
          for (int c = 0; c < 3; ++c) {
            x[c] += bv[j] * a[at][c];
            xt[c] += dbv[j] * a[at][c];
            xu[c] += bv[j] * au[at][c];
          }
        }
        value[std::size_t(i) * n2 + w] = x;
        dt[std::size_t(i) * n2 + w] = xt;
        du[std::size_t(i) * n2 + w] = xu;
      }
    // Along i: the Jacobian's three columns at every (s, w) of this t.
    for (int m = 0; m < n0; ++m) {
      const double* bm = &b0[std::size_t(m) * (d0 + 1)];
      const double* dbm = &db0[std::size_t(m) * (d0 + 1)];
      for (int w = 0; w < n2; ++w) {
        Mat3 j{};
        for (int i = 0; i <= d0; ++i) {
          const std::size_t at = std::size_t(i) * n2 + w;
          for (int c = 0; c < 3; ++c) {
            j[c][0] += dbm[i] * value[at][c];
            j[c][1] += bm[i] * dt[at][c];
            j[c][2] += bm[i] * du[at][c];
          }
        }
        const double det = determinant(j);
        signs[(std::size_t(m) * n1 + v) * n2 + w] = det > 0 ? 1 : det < 0 ? -1 : 0;
      }
    }
  }
  int sign = 0;
  for (int ci = 0; ci < d0; ++ci)
    for (int cj = 0; cj < d1; ++cj)
      for (int ck = 0; ck < d2; ++ck)
        for (int sa = 0; sa < samples; ++sa)
          for (int sb = 0; sb < samples; ++sb)
            for (int sc = 0; sc < samples; ++sc) {
              const int m = ci * samples + sa, v = cj * samples + sb, w = ck * samples + sc;
              const int sg = signs[(std::size_t(m) * n1 + v) * n2 + w];
              if (sign == 0) sign = sg;
              if (sg == 0 || sg != sign)
                return Fold{{ci, cj, ck},
                            {(ci + (sa + 0.5) / samples) / d0, (cj + (sb + 0.5) / samples) / d1,
                             (ck + (sc + 0.5) / samples) / d2}};
            }
  return std::nullopt;
}

}  // namespace frep

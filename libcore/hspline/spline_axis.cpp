#include "hspline/spline_axis.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "base/errors.h"

namespace frep {

namespace {

[[noreturn]] void refuse(const char* what, const std::string& why) {
  throw ModelError(std::string(what) + ": " + why);
}

// Non-decreasing, finite, no knot repeated more than `most` times.
void checkSequence(const std::vector<double>& knots, const char* what, int most) {
  int run = 1;
  for (std::size_t k = 0; k < knots.size(); ++k) {
    if (!std::isfinite(knots[k]))
      refuse(what, "knot " + std::to_string(k) + " is not a finite number");
    if (k == 0) continue;
    if (knots[k] < knots[k - 1])
      refuse(what, "knot " + std::to_string(k) + " (" + std::to_string(knots[k]) +
                       ") is smaller than the one before it; knots must not decrease");
    run = knots[k] == knots[k - 1] ? run + 1 : 1;
    if (run > most)
      refuse(what, "knot " + std::to_string(knots[k]) + " is repeated " + std::to_string(run) +
                       " times; a cubic allows at most " + std::to_string(most) +
                       " inside the domain");
  }
}

long floorDiv(long a, long b) {
  long q = a / b;
  if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
  return q;
}

}  // namespace

SplineAxis SplineAxis::open(std::vector<double> knots, const char* what) {
  if (knots.size() < 8)
    refuse(what, "an open cubic axis needs at least 8 knots (4 control vertices), got " +
                     std::to_string(knots.size()));
  // Interior knots at most triple; the end ones may be quadruple (clamped).
  std::vector<double> inner(knots.begin() + 1, knots.end() - 1);
  checkSequence(knots, what, 4);
  checkSequence(inner, what, 3);
  SplineAxis a;
  a.count_ = static_cast<int>(knots.size()) - 4;
  a.knots_ = std::move(knots);
  if (!(a.knots_[3] < a.knots_[a.count_]))
    refuse(what, "the domain [knot 3, knot " + std::to_string(a.count_) + "] is empty");
  return a;
}

SplineAxis SplineAxis::periodic(std::vector<double> knots, double period, const char* what) {
  if (knots.size() < 4)
    refuse(what, "a periodic cubic axis needs at least 4 control vertices, got " +
                     std::to_string(knots.size()));
  if (!(std::isfinite(period) && period > 0)) refuse(what, "the period must be a positive number");
  checkSequence(knots, what, 3);
  if (!(knots.back() < knots.front() + period))
    refuse(what, "the knots must lie within one period [first knot, first knot + period)");
  SplineAxis a;
  a.periodic_ = true;
  a.count_ = static_cast<int>(knots.size());
  a.period_ = period;
  a.knots_ = std::move(knots);
  // Multiplicity across the seam counts too.
  int run = 1;
  for (int k = 1; k < a.count_ + 3; ++k) {
    run = a.knot(k) == a.knot(k - 1) ? run + 1 : 1;
    if (run > 3) refuse(what, "a knot is repeated more than 3 times across the period's seam");
  }
  return a;
}

SplineAxis SplineAxis::clampedUniform(int spans) {
  if (spans < 1) throw ModelError("a clamped axis needs at least one span");
  std::vector<double> k;
  for (int i = 0; i < 3; ++i) k.push_back(0);
  for (int i = 0; i <= spans; ++i) k.push_back(i);
  for (int i = 0; i < 3; ++i) k.push_back(spans);
  return open(std::move(k));
}

SplineAxis SplineAxis::periodicUniform(int count) {
  std::vector<double> k;
  for (int i = 0; i < count; ++i) k.push_back(i);
  return periodic(std::move(k), count);
}

double SplineAxis::knot(long k) const {
  if (!periodic_) return knots_[static_cast<std::size_t>(std::clamp<long>(k, 0, count_ + 3))];
  const long q = floorDiv(k, count_);
  return knots_[static_cast<std::size_t>(k - q * count_)] + static_cast<double>(q) * period_;
}

double SplineAxis::lo() const {
  return periodic_ ? knots_[0] : knots_[3];
}
double SplineAxis::hi() const {
  return periodic_ ? knots_[0] + period_ : knots_[count_];
}

int SplineAxis::wrap(long i) const {
  if (periodic_) return static_cast<int>(i - floorDiv(i, count_) * count_);
  return i >= 0 && i < count_ ? static_cast<int>(i) : -1;
}

long SplineAxis::extendedSpan(double t) const {
  if (!periodic_) {
    t = std::clamp(t, lo(), hi());
    auto first = knots_.begin() + 3, last = knots_.begin() + count_ + 1;
    long s = static_cast<long>(std::upper_bound(first, last, t) - knots_.begin()) - 1;
    if (s >= count_) s = count_ - 1;
    while (s > 3 && !(knots_[s] < knots_[s + 1])) --s;
    return s;
  }
  long q = static_cast<long>(std::floor((t - lo()) / period_));
  double w = t - static_cast<double>(q) * period_;
  if (w >= hi()) w -= period_, ++q;
  if (w < lo()) w += period_, --q;
  long r =
      static_cast<long>(std::upper_bound(knots_.begin(), knots_.end(), w) - knots_.begin()) - 1;
  r = std::max<long>(r, 0);
  return r + q * count_;
}

SpanBasis SplineAxis::basis(double t) const {
  constexpr int p = kDegree;
  SpanBasis out;
  long s = extendedSpan(t);
  double x;
  if (periodic_) {
    // Work in the period holding span s's wrapped copy, so large t keep their precision.
    const long q = floorDiv(s, count_);
    s -= q * count_;
    x = t - static_cast<double>(q) * period_;
  } else {
    x = std::clamp(t, lo(), hi());
  }
  out.span = static_cast<int>(s);
  // The NURBS Book's algorithm A2.3 (basis functions and derivatives), for degree 3.
  double ndu[p + 1][p + 1], left[p + 1], right[p + 1];
  ndu[0][0] = 1;
  for (int j = 1; j <= p; ++j) {
    left[j] = x - knot(s + 1 - j);
    right[j] = knot(s + j) - x;
    double saved = 0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  double ders[3][p + 1];
  for (int j = 0; j <= p; ++j) ders[0][j] = ndu[j][p];
  double a[2][p + 1];
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1;
    for (int k = 1; k <= 2; ++k) {
      double d = 0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      std::swap(s1, s2);
    }
  }
  for (int j = 0; j <= p; ++j) {
    out.value[j] = ders[0][j];
    out.first[j] = ders[1][j] * p;
    out.second[j] = ders[2][j] * p * (p - 1);
  }
  return out;
}

double SplineAxis::reference(int i) const {
  const double g = (knot(i + 1) + knot(i + 2) + knot(i + 3)) / 3;
  return periodic_ ? g : std::clamp(g, lo(), hi());
}

SplineAxis SplineAxis::refined() const {
  std::vector<double> k;
  if (periodic_) {
    for (int i = 0; i < count_; ++i) {
      k.push_back(knot(i));
      if (knot(i) < knot(i + 1)) k.push_back(0.5 * (knot(i) + knot(i + 1)));
    }
    return periodic(std::move(k), period_);
  }
  for (int i = 0; i < count_ + 4; ++i) {
    k.push_back(knots_[i]);
    if (i >= 3 && i < count_ && knots_[i] < knots_[i + 1])
      k.push_back(0.5 * (knots_[i] + knots_[i + 1]));
  }
  return open(std::move(k));
}

std::vector<RefinementRow> SplineAxis::rowsOnto(const SplineAxis& fine) const {
  std::vector<RefinementRow> rows(static_cast<std::size_t>(fine.count()));
  for (int j = 0; j < fine.count(); ++j) {
    // A fine span of positive length under fine vertex j (inside the domain): the coarse
    // polynomial there, blossomed at j's three inner knots, is j's coefficient.
    long m = -1;
    for (long c : {j + 1L, j + 2L, j + 0L, j + 3L}) {
      if (!fine.periodic_ && (c < 3 || c > fine.count() - 1)) continue;
      if (fine.knot(c) < fine.knot(c + 1)) {
        m = c;
        break;
      }
    }
    if (m < 0) continue;
    const long s = extendedSpan(0.5 * (fine.knot(m) + fine.knot(m + 1)));
    // Blossom by de Boor's triangle with one argument per stage; weights over s-3..s.
    double d[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
    for (int k = 1; k <= 3; ++k) {
      const double x = fine.knot(j + k);
      for (int q = 3; q >= k; --q) {
        const long r = s - 3 + q;
        const double a = (x - knot(r)) / (knot(r + 4 - k) - knot(r));
        for (int c = 0; c < 4; ++c) d[q][c] = (1 - a) * d[q - 1][c] + a * d[q][c];
      }
    }
    for (int c = 0; c < 4; ++c)
      if (d[3][c] != 0) rows[static_cast<std::size_t>(j)].emplace_back(wrap(s - 3 + c), d[3][c]);
  }
  return rows;
}

std::vector<int> SplineAxis::childCentres(const SplineAxis& fine) const {
  std::vector<double> g(static_cast<std::size_t>(fine.count()));
  for (int j = 0; j < fine.count(); ++j)
    g[j] = (fine.knot(j + 1) + fine.knot(j + 2) + fine.knot(j + 3)) / 3;
  std::vector<int> centre(static_cast<std::size_t>(count_));
  for (int i = 0; i < count_; ++i) {
    const double r = (knot(i + 1) + knot(i + 2) + knot(i + 3)) / 3;
    int best = 0;
    double bestDistance = INFINITY;
    for (double shift :
         periodic_ ? std::vector<double>{-period_, 0, period_} : std::vector<double>{0}) {
      const double target = r + shift;
      const long at = std::lower_bound(g.begin(), g.end(), target) - g.begin();
      for (long c = at - 1; c <= at; ++c) {
        if (c < 0 || c >= fine.count()) continue;
        const double distance = std::abs(g[static_cast<std::size_t>(c)] - target);
        if (distance < bestDistance - 1e-12 * (1 + std::abs(target)))
          bestDistance = distance, best = static_cast<int>(c);
      }
    }
    centre[static_cast<std::size_t>(i)] = best;
  }
  return centre;
}

}  // namespace frep

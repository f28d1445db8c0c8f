// One parameter direction of a cubic B-spline: its knots, its basis, its reference parameters
// and the coefficients that carry a spline onto a finer knot vector (refinement and flattening).
#pragma once

#include <array>
#include <utility>
#include <vector>

namespace frep {

// The four basis functions that are not zero on one span, with their first and second
// derivatives: value[q] belongs to control vertex span - 3 + q.
struct SpanBasis {
  int span = 0;  // extended span index (periodic axes: may lie outside [0, count))
  std::array<double, 4> value{}, first{}, second{};
};

// One row of a refinement: the coarse control vertices (index, weight) a fine one is made of.
using RefinementRow = std::vector<std::pair<int, double>>;

class SplineAxis {
 public:
  static constexpr int kDegree = 3;

  // An open axis: count + 4 non-decreasing knots (clamped or not); the domain is
  // [knot(3), knot(count)]. Throws ModelError naming `what` on a bad vector.
  static SplineAxis open(std::vector<double> knots, const char* what = "knots");
  // A periodic axis: `knots` holds count knots in [knots[0], knots[0] + period); control vertex
  // i's basis spans [knot(i), knot(i + 4)] with knots extended by the period.
  static SplineAxis periodic(std::vector<double> knots, double period, const char* what = "knots");
  // Uniform axes: an open clamped one of `spans` spans over [0, spans], a periodic one of
  // `count` spans over [0, count).
  static SplineAxis clampedUniform(int spans);
  static SplineAxis periodicUniform(int count);

  int count() const { return count_; }
  bool isPeriodic() const { return periodic_; }
  double period() const { return period_; }
  // The knot sequence as stored: count + 4 knots (open) or count knots (periodic).
  const std::vector<double>& knots() const { return knots_; }
  // Knot k; periodic axes extend their knots by the period to any k.
  double knot(long k) const;
  double lo() const;
  double hi() const;
  // Control vertex index i wrapped into [0, count) on a periodic axis; -1 when an open axis
  // has no such vertex.
  int wrap(long i) const;

  // The span holding t (periodic axes wrap t first), with the basis there.
  SpanBasis basis(double t) const;
  // The reference parameter of control vertex i: its Greville abscissa (the mean of its three
  // inner knots), which is where a uniform cubic basis function peaks; kept inside the domain.
  double reference(int i) const;
  // The same axis with the midpoint of every span of positive length inside the domain
  // inserted: twice the knot density, as a refinement level has.
  SplineAxis refined() const;
  // For every control vertex of `fine`, whose knots hold these knots (same domain), the
  // coarse vertices and weights that give the same curve: knot insertion, exactly (Oslo).
  std::vector<RefinementRow> rowsOnto(const SplineAxis& fine) const;
  // For each control vertex, the fine vertex of refined() that peaks nearest to it: the
  // centre of the block a refinement of that vertex creates.
  std::vector<int> childCentres(const SplineAxis& fine) const;

  bool operator==(const SplineAxis& o) const {
    return periodic_ == o.periodic_ && count_ == o.count_ && period_ == o.period_ &&
           knots_ == o.knots_;
  }

 private:
  // The extended span index s with knot(s) <= t < knot(s + 1), t not wrapped.
  long extendedSpan(double t) const;
  bool periodic_ = false;
  int count_ = 0;
  double period_ = 0;
  std::vector<double> knots_;
};

}  // namespace frep

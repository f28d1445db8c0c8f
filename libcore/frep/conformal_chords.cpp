// Straight struts of cells that follow a cylinder or a sphere (conformal_chords.h).
#include "frep/conformal_chords.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "frep/node_helpers.h"
#include "frep/periodic_segments.h"

namespace frep {

namespace {

// Layers of a sphere: the radial index times this plus the latitude's (at most a half turn of
// cells, far fewer than this).
constexpr long long kLatitudes = 1 << 20;
constexpr double kLayerBins = 256.0;
std::atomic<std::uint64_t> fieldsMade{0};

}  // namespace

double conformalExactWithin(const Vec3& size, double blend, double radius, double nodeRadius) {
  return std::max(
      {0.5 * std::min({size[0], size[1], size[2]}) + blend, 2.0 * radius, 2.0 * nodeRadius});
}

double largestLayerStruts(const ConformalCells& cells, double exactWithin) {
  const Vec3& size = cells.size;
  const double reach = exactWithin + std::max({size[0], size[1], size[2]});
  const double out = std::ceil(2.0 * reach / size[0]) + 2.0;
  const double round = cells.around + 3.0;
  const double along =
      cells.sphere ? std::ceil(0.5 * cells.around) + 2.0 : std::ceil(2.0 * reach / size[2]) + 2.0;
  return out * round * along * double(cells.cell->struts.size());
}

ConformalChordsField::ConformalChordsField(const ConformalCells& cells, double exactWithin,
                                           bool nodes)
    : cells_(cells), nodes_(nodes), id_(++fieldsMade) {
  const Frame f = frameAlong(cells.axis);
  u_ = f.u, v_ = f.v, w_ = f.w;
  const double perTurn = cells.around / (2.0 * kPi);
  alongY_ = perTurn * cells.size[1];
  alongZ_ = perTurn * cells.size[2];
  wedge_ = 2.0 * kPi / cells.around;
  exact_ = exactWithin;
  const double blend = nodes ? 0.0 : cells.blend;
  cap_ = exactWithin - 0.5 * blend;
}

Vec3 ConformalChordsField::toWorld(const Vec3& q) const {
  const double angle = q[1] / alongY_;
  Vec3 l;
  if (cells_.sphere) {
    const double fromPole = q[2] / alongZ_;
    l = {q[0] * std::sin(fromPole) * std::cos(angle), q[0] * std::sin(fromPole) * std::sin(angle),
         q[0] * std::cos(fromPole)};
  } else {
    l = {q[0] * std::cos(angle), q[0] * std::sin(angle), q[2]};
  }
  return vadd(cells_.origin, vadd(vscale(u_, l[0]), vadd(vscale(v_, l[1]), vscale(w_, l[2]))));
}

std::vector<StrutPiece> ConformalChordsField::chordsIn(const Box3& box) const {
  const Vec3& size = cells_.size;
  const double pole = kPi * alongZ_, halfTurn = kPi * alongY_;
  const Vec3 lo{0.0, -HUGE_VAL, cells_.sphere ? 0.0 : -HUGE_VAL};
  const Vec3 hi{HUGE_VAL, HUGE_VAL, cells_.sphere ? pole : HUGE_VAL};
  // A box spanning a turn or more takes each strut once: the one whose middle is in the turn
  // round the angle 0 (its copies a turn away have the same chord).
  const bool wholeTurn = box.hi[1] - box.lo[1] >= 2.0 * halfTurn;
  auto once = [&](const StrutPiece& s) {
    const double middle = 0.5 * (s.a[1] + s.b[1]);
    return !wholeTurn || (middle >= -halfTurn && middle < halfTurn);
  };
  std::vector<StrutPiece> out;
  StrutPiece piece;
  if (nodes_) {
    long long from[3], to[3];
    for (int a = 0; a < 3; ++a) {
      from[a] = (long long)std::floor(box.lo[a] / size[a]);
      to[a] = (long long)std::floor(box.hi[a] / size[a]);
    }
    for (long long i = from[0]; i <= to[0]; ++i)
      for (long long j = from[1]; j <= to[1]; ++j)
        for (long long k = from[2]; k <= to[2]; ++k)
          for (const Vec3& n : cells_.cell->nodes) {
            const Vec3 q{(n[0] + double(i)) * size[0], (n[1] + double(j)) * size[1],
                         (n[2] + double(k)) * size[2]};
            bool in = true;
            for (int a = 0; a < 3; ++a)
              in = in && q[a] >= std::max(box.lo[a], lo[a]) && q[a] <= std::min(box.hi[a], hi[a]);
            if (in && once({q, q})) out.push_back({toWorld(q), toWorld(q)});
          }
    return out;
  }
  for (const StrutPiece& s : strutsInBox(*cells_.cell, size, {0, 0, 0}, box))
    if (once(s) && clip(s.a, s.b, lo, hi, &piece))
      out.push_back({toWorld(piece.a), toWorld(piece.b)});
  return out;
}

ConformalChordsField::Folded ConformalChordsField::fold(const Vec3& p) const {
  const Vec3 d = vsub(p, cells_.origin);
  const double l0 = vdot(d, u_), l1 = vdot(d, v_), l2 = vdot(d, w_);
  Folded f;
  const double k = std::floor(std::atan2(l1, l0) / wedge_);
  f.turn = k * wedge_;
  const double c = std::cos(f.turn), s = std::sin(f.turn);
  f.q = {l0 * c + l1 * s, -l0 * s + l1 * c, l2};
  const double across = std::sqrt(f.q[0] * f.q[0] + f.q[1] * f.q[1]);
  // Farther than a billion cells out, where doubles no longer tell the chords apart (and the
  // layer numbers would overflow), no layer is made: the point is taken as outside every
  // strut, at the cap.
  const double farthest = 1e9 * cells_.size[0];
  if (!(across < farthest) || !(std::abs(f.q[2]) < farthest)) {
    f.far = true;
    return f;
  }
  if (cells_.sphere) {
    const double distance = std::sqrt(across * across + f.q[2] * f.q[2]);
    const long long i = (long long)std::floor(distance / cells_.size[0]);
    const long long latitudes = (long long)std::ceil(kPi * alongZ_ / cells_.size[2] - 1e-9);
    const long long j = std::min(
        std::max((long long)std::floor(std::atan2(across, f.q[2]) * alongZ_ / cells_.size[2]), 0LL),
        latitudes - 1);
    f.layer = i * kLatitudes + j;
  } else {
    const double m = std::floor(f.q[2] / cells_.size[2]);
    f.q[2] -= m * cells_.size[2];
    f.layer = (long long)std::floor(across / cells_.size[0]);
  }
  return f;
}

const PeriodicSegmentsField* ConformalChordsField::layer(long long key) const {
  // A thread's points come mostly from one layer after another: its last layer is kept aside
  // (by the field's own number, never reused, so another field at this address cannot hit),
  // which spares the shared lock on most points. Layers live as long as the field.
  struct Last {
    std::uint64_t field = 0;
    long long key = 0;
    const PeriodicSegmentsField* layer = nullptr;
  };
  thread_local Last last;
  if (last.field == id_ && last.key == key) return last.layer;
  const PeriodicSegmentsField* found = madeLayer(key);
  last = {id_, key, found};
  return found;
}

const PeriodicSegmentsField* ConformalChordsField::madeLayer(long long key) const {
  {
    std::shared_lock<std::shared_mutex> read(mutex_);
    const auto at = layers_.find(key);
    if (at != layers_.end()) return at->second.get();
  }
  // The cells whose chords may come within exact_ of a point of the layer's wedge: `reach`
  // cells beyond it out from the axis (or centre) and along it (or from the pole), and round
  // the axis as many as an arc of that reach takes at the layer's inner radius (near the axis
  // or a pole the whole turn).
  const Vec3& size = cells_.size;
  const long long i = cells_.sphere ? key / kLatitudes : key;
  const long long j = cells_.sphere ? key % kLatitudes : 0;
  const double smallest = std::min({size[0], size[1], size[2]});
  const double largest = std::max({size[0], size[1], size[2]});
  const double reach = exact_ + largest;  // (a chord strays from its curve by less than a cell)
  Box3 box;
  box.lo[0] = std::max(0.0, double(i) * size[0] - reach);
  box.hi[0] = double(i + 1) * size[0] + reach;
  // the angle that `reach` spans at a radius (a chord of that length), or a half turn
  auto angleAt = [reach](double radius) {
    return reach < 2.0 * radius ? 2.0 * std::asin(reach / (2.0 * radius)) : kPi;
  };
  double inner = box.lo[0];
  if (cells_.sphere) {
    const double pole = kPi * alongZ_, span = angleAt(inner) * alongZ_;
    box.lo[2] = std::max(0.0, double(j) * size[2] - span);
    box.hi[2] = std::min(pole, double(j + 1) * size[2] + span);
    // the longitude's arcs narrow with the sine of the latitude
    const double a = box.lo[2] / alongZ_, b = box.hi[2] / alongZ_;
    const double least =
        (a <= 0.5 * kPi && b >= 0.5 * kPi) ? 1.0 : std::min(std::sin(a), std::sin(b));
    inner *= std::max(0.0, least);
  } else {
    box.lo[2] = -reach;
    box.hi[2] = size[2] + reach;
  }
  // round the axis: the arc at `inner` that reach spans, in the lattice's arc units
  const double turn = 2.0 * kPi * alongY_;
  const double arc = angleAt(inner) * alongY_;
  if (arc >= 0.5 * turn) {
    box.lo[1] = -0.5 * turn - size[1];
    box.hi[1] = 0.5 * turn + size[1];
  } else {
    box.lo[1] = -arc - size[1];
    box.hi[1] = size[1] + arc + size[1];
  }
  std::vector<StrutPiece> chords = chordsIn(box);
  // the chords in the wedge's frame (the point's folded coordinates: origin 0, frame axes)
  for (StrutPiece& s : chords)
    for (Vec3* p : {&s.a, &s.b}) {
      const Vec3 d = vsub(*p, cells_.origin);
      *p = {vdot(d, u_), vdot(d, v_), vdot(d, w_)};
    }
  std::shared_ptr<const PeriodicSegmentsField> made;
  if (!chords.empty()) {
    // The bins cover the wedge's cell of the layer, where its points are (its box from a grid of
    // its points, grown by a twentieth of a cell for the curve between them and the rounding
    // of the fold).
    const Vec3 from{double(i) * size[0], 0.0, cells_.sphere ? double(j) * size[2] : 0.0};
    const double pole = cells_.sphere ? kPi * alongZ_ : HUGE_VAL;
    Box3 cell{{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
    for (int a = 0; a <= 8; ++a)
      for (int b = 0; b <= 8; ++b)
        for (int c = 0; c <= 8; ++c) {
          const Vec3 q{from[0] + a / 8.0 * size[0], b / 8.0 * size[1],
                       std::min(from[2] + c / 8.0 * size[2], pole)};
          const Vec3 d = vsub(toWorld(q), cells_.origin);
          const Vec3 l{vdot(d, u_), vdot(d, v_), vdot(d, w_)};
          cell = boxHull(cell, {l, l});
        }
    // Bins of half the cell's shortest side, at most kLayerBins of them: each bin's set-up
    // looks at the layer's chords round it.
    std::array<int, 3> bins{};
    const double grow = 0.05 * smallest;
    for (int a = 0; a < 3; ++a) {
      cell.lo[a] -= grow;
      cell.hi[a] += grow;
    }
    // Only the chords that come within exact_ and the blend of the cell matter to its points
    // (the distance is capped beyond); the rest of the turn is dropped before binning, which
    // would otherwise look at every one of them from every bin.
    const double near = exact_ + (nodes_ ? 0.0 : cells_.blend) + 1e-9 * (exact_ + largest);
    chords.erase(std::remove_if(chords.begin(), chords.end(),
                                [&](const StrutPiece& s) {
                                  for (int a = 0; a < 3; ++a)
                                    if (std::min(s.a[a], s.b[a]) > cell.hi[a] + near ||
                                        std::max(s.a[a], s.b[a]) < cell.lo[a] - near)
                                      return true;
                                  return false;
                                }),
                 chords.end());
    const Vec3 extent = vsub(cell.hi, cell.lo);
    // (far out a wedge's cell is long round the axis and thin across: the side grows until
    // the bins are few enough)
    double side =
        std::max(0.5 * smallest, std::cbrt(extent[0] * extent[1] * extent[2] / kLayerBins));
    for (;; side *= 1.25) {
      double count = 1.0;
      for (int a = 0; a < 3; ++a) count *= std::max(1.0, std::ceil(extent[a] / side));
      if (count <= kLayerBins) break;
    }
    for (int a = 0; a < 3; ++a) bins[a] = std::max(1, int(std::ceil(extent[a] / side)));
    if (!chords.empty())
      made = PeriodicSegmentsField::unrepeated(chords, cell, bins, exact_,
                                               nodes_ ? 0.0 : cells_.blend);
  }
  // (null for a layer with no chord within reach: its points are all at the cap)
  std::unique_lock<std::shared_mutex> write(mutex_);
  return layers_.emplace(key, made).first->second.get();  // (another thread's, if it won)
}

std::size_t ConformalChordsField::layersMade() const {
  std::shared_lock<std::shared_mutex> read(mutex_);
  return layers_.size();
}

double ConformalChordsField::value(const Vec3& p, double gradient[3]) const {
  const Folded f = fold(p);
  const PeriodicSegmentsField* near = f.far ? nullptr : layer(f.layer);
  if (!near) {
    if (gradient) gradient[0] = gradient[1] = gradient[2] = 0.0;
    return cap_;
  }
  if (!gradient) return near->eval(f.q[0], f.q[1], f.q[2]);
  const Dual d =
      near->evalGradient(Dual(f.q[0], 1, 0, 0), Dual(f.q[1], 0, 1, 0), Dual(f.q[2], 0, 0, 1));
  // back from the wedge: turned by +turn about the axis, then out of the frame
  const double c = std::cos(f.turn), s = std::sin(f.turn);
  const double g0 = d.d[0] * c - d.d[1] * s, g1 = d.d[0] * s + d.d[1] * c, g2 = d.d[2];
  for (int a = 0; a < 3; ++a) gradient[a] = u_[a] * g0 + v_[a] * g1 + w_[a] * g2;
  return d.v;
}

double ConformalChordsField::eval(double x, double y, double z) const {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    return std::numeric_limits<double>::quiet_NaN();
  return value({x, y, z}, nullptr);
}

Dual ConformalChordsField::evalGradient(const Dual& x, const Dual& y, const Dual& z) const {
  if (!std::isfinite(x.v) || !std::isfinite(y.v) || !std::isfinite(z.v))
    return Dual(std::numeric_limits<double>::quiet_NaN());
  double g[3];
  const double d = value({x.v, y.v, z.v}, g);
  return composed(d, g, x, y, z);
}

Interval ConformalChordsField::evalInterval(const Interval& x, const Interval& y,
                                            const Interval& z) const {
  const double blend = nodes_ ? 0.0 : cells_.blend;
  const double least = std::min(-0.5 * blend * (1.0 + 1e-12), cap_);
  const Interval* box[3] = {&x, &y, &z};
  double centre[3], half2 = 0.0, largest = 0.0;
  for (int a = 0; a < 3; ++a) {
    const Interval& iv = *box[a];
    if (iv.nan || !std::isfinite(iv.lo) || !std::isfinite(iv.hi)) return {least, cap_, iv.nan};
    centre[a] = 0.5 * (iv.lo + iv.hi);
    const double w = 0.5 * (iv.hi - iv.lo);
    half2 += w * w;
    largest = std::max({largest, std::abs(iv.lo), std::abs(iv.hi)});
  }
  // min(the blended distance, cap_) is 1-Lipschitz but for the blend: the blended distance lies
  // within blend / 2 below the nearest chord's, which is 1-Lipschitz. The margin covers the
  // rounding of the fold (a turn and a move of the point) and of the values.
  const double half = std::sqrt(half2) * (1.0 + 1e-12);
  const double v = value({centre[0], centre[1], centre[2]}, nullptr);
  const double margin = 1e-11 * (std::abs(v) + half + blend + largest + exact_);
  return {std::min(std::max(least, v - half - 0.5 * blend - margin), cap_),
          std::min(v + 0.5 * blend + half + margin, cap_)};
}

}  // namespace frep

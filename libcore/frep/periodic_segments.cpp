// The binned periodic segment distance (periodic_segments.h).
#include "frep/periodic_segments.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace frep {

namespace {

// |p - s|^2 for the segment from a along e, and the offset from p to its closest point.
inline double segmentOffset2(const double p[3], const double a[3], const double e[3],
                             double inverseLength2, double offset[3]) {
  const double d[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  double t = (d[0] * e[0] + d[1] * e[1] + d[2] * e[2]) * inverseLength2;
  t = std::min(std::max(t, 0.0), 1.0);
  offset[0] = a[0] + t * e[0] - p[0];
  offset[1] = a[1] + t * e[1] - p[1];
  offset[2] = a[2] + t * e[2] - p[2];
  return offset[0] * offset[0] + offset[1] * offset[1] + offset[2] * offset[2];
}

// |p - s| (the same rounding as the square root of segmentOffset2).
inline double segmentOffset(const double p[3], const double a[3], const double e[3],
                            double inverseLength2, double offset[3]) {
  return std::sqrt(segmentOffset2(p, a, e, inverseLength2, offset));
}

double segmentDistance(const Vec3& p, const StrutPiece& s) {
  const double pp[3] = {p[0], p[1], p[2]}, a[3] = {s.a[0], s.a[1], s.a[2]};
  const double e[3] = {s.b[0] - s.a[0], s.b[1] - s.a[1], s.b[2] - s.a[2]};
  const double l2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
  double offset[3];
  return segmentOffset(pp, a, e, l2 > 0.0 ? 1.0 / l2 : 0.0, offset);
}

}  // namespace

PeriodicSegmentsField::PeriodicSegmentsField(const std::vector<StrutPiece>& segments,
                                             const Vec3& period, const Vec3& origin,
                                             const std::array<int, 3>& bins, double blend)
    : PeriodicSegmentsField(segments, period, origin, bins, blend, true, 0.0) {}

std::shared_ptr<const PeriodicSegmentsField> PeriodicSegmentsField::unrepeated(
    const std::vector<StrutPiece>& segments, const Box3& box, const std::array<int, 3>& bins,
    double exactWithin, double blend) {
  return std::shared_ptr<const PeriodicSegmentsField>(new PeriodicSegmentsField(
      segments, vsub(box.hi, box.lo), box.lo, bins, blend, false, exactWithin));
}

PeriodicSegmentsField::PeriodicSegmentsField(const std::vector<StrutPiece>& segments,
                                             const Vec3& period, const Vec3& origin,
                                             const std::array<int, 3>& bins, double blend,
                                             bool repeated, double exactWithin)
    : tile_(segments),
      period_(period),
      origin_(origin),
      bins_(bins),
      blend_(blend),
      repeated_(repeated) {
  if (segments.empty()) throw std::invalid_argument("a periodic network needs a segment");
  double longest = 0.0;
  for (const StrutPiece& s : segments) longest = std::max(longest, vlength(vsub(s.b, s.a)));
  for (int a = 0; a < 3; ++a) {
    binSize_[a] = period[a] / bins[a];
    // (a bin of no size would never reach its neighbours' segments)
    if (!(binSize_[a] > 0.0) || !std::isfinite(binSize_[a]) || bins[a] < 1)
      throw std::invalid_argument("a segment network's bins need a positive finite size");
  }
  const double halfDiagonal = 0.5 * vlength(binSize_);
  const double smallestBin = std::min({binSize_[0], binSize_[1], binSize_[2]});
  const double largestBin = std::max({binSize_[0], binSize_[1], binSize_[2]});
  const double shortestPeriod = std::min({period[0], period[1], period[2]});

  // The copies in the tile and the 26 round it (unrepeated: the segments), each filed in the
  // cells (bin-sized, over those 27 tiles) its box meets, so that a bin looks only at the
  // copies near it.
  std::vector<StrutPiece> copies;
  const int tiles = repeated ? 1 : 0;  // tiles each side of the bins' own
  for (int i = -tiles; i <= tiles; ++i)
    for (int j = -tiles; j <= tiles; ++j)
      for (int k = -tiles; k <= tiles; ++k) {
        const Vec3 shift{i * period[0], j * period[1], k * period[2]};
        for (const StrutPiece& s : segments) copies.push_back({vadd(s.a, shift), vadd(s.b, shift)});
      }
  const int span = 2 * tiles + 1;
  const int cells[3] = {span * bins[0], span * bins[1], span * bins[2]};
  const int offset[3] = {tiles * bins[0], tiles * bins[1], tiles * bins[2]};  // the bins' own
  auto cellOf = [&](double v, int a) {
    const int i = int(std::floor((v - origin[a] + tiles * period[a]) / binSize_[a]));
    return std::min(std::max(i, 0), cells[a] - 1);
  };
  std::vector<std::vector<std::uint32_t>> filed(std::size_t(cells[0]) * cells[1] * cells[2]);
  for (std::size_t c = 0; c < copies.size(); ++c) {
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = cellOf(std::min(copies[c].a[a], copies[c].b[a]), a);
      hi[a] = cellOf(std::max(copies[c].a[a], copies[c].b[a]), a);
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x)
          filed[(std::size_t(z) * cells[1] + y) * cells[0] + x].push_back(std::uint32_t(c));
  }

  std::vector<std::int64_t> kept(copies.size(), -1);  // index in segments_
  std::vector<std::uint32_t> seen(copies.size(), 0);
  std::uint32_t visit = 0;
  std::vector<std::pair<double, std::uint32_t>> near;
  binStart_.assign(1, 0);
  for (int bz = 0; bz < bins[2]; ++bz)
    for (int by = 0; by < bins[1]; ++by)
      for (int bx = 0; bx < bins[0]; ++bx) {
        const int b[3] = {bx, by, bz};
        Vec3 centre;
        for (int a = 0; a < 3; ++a) centre[a] = origin[a] + (b[a] + 0.5) * binSize_[a];
        // Boxes of cells round the bin, reaching `reach` from its centre along each axis,
        // until one holds every copy within `keep`: a copy filed in no cell of the box is
        // farther than `reach` from the centre.
        for (double reach = 1.5 * largestBin;;) {
          ++visit;
          near.clear();
          int from[3], to[3];
          bool everyCell = true;  // unrepeated: then every segment was seen
          for (int a = 0; a < 3; ++a) {
            const int r = int(std::ceil(reach / binSize_[a] - 0.5));
            from[a] = std::max(0, b[a] + offset[a] - r);
            to[a] = std::min(cells[a] - 1, b[a] + offset[a] + r);
            everyCell = everyCell && from[a] == 0 && to[a] == cells[a] - 1;
          }
          double least = std::numeric_limits<double>::infinity();
          for (int z = from[2]; z <= to[2]; ++z)
            for (int y = from[1]; y <= to[1]; ++y)
              for (int x = from[0]; x <= to[0]; ++x)
                for (std::uint32_t c : filed[(std::size_t(z) * cells[1] + y) * cells[0] + x]) {
                  if (seen[c] == visit) continue;
                  seen[c] = visit;
                  const double d = segmentDistance(centre, copies[c]);
                  near.push_back({d, c});
                  least = std::min(least, d);
                }
          // A point of the bin is within least + h of some copy, so its nearest copy is
          // within least + 2h of the centre, and a copy the blend reaches within `blend`
          // more; the margin covers rounding.
          // Unrepeated, a point farther than exactWithin from every segment needs no exact
          // distance: its nearest is then farther than exactWithin + h from the centre (the
          // bin keeps at least the centre's nearest, for a finite upper bound).
          double keep = least + 2.0 * halfDiagonal + blend;
          if (!repeated) keep = std::min(keep, std::max(least, exactWithin + halfDiagonal + blend));
          keep += 1e-9 * (least + halfDiagonal + blend);
          // Only copies in the tiles next to the bin's are filed: a copy two tiles away has
          // its middle more than a period from the centre.
          if (repeated && keep > shortestPeriod - 0.5 * longest)
            throw std::invalid_argument("the period is too short for the network's segments");
          if (keep >= reach && !(everyCell && !repeated)) {  // again, reaching `keep`
            // (unrepeated, twice as far at least: segments may lie far beyond the bins)
            reach = repeated
                        ? std::max(keep * (1.0 + 1e-9), reach + smallestBin)
                        : std::max(std::isfinite(keep) ? keep * (1.0 + 1e-9) : 0.0, 2.0 * reach);
            continue;
          }
          farthest_ = std::max(farthest_, least + halfDiagonal);
          near.erase(std::remove_if(
                         near.begin(), near.end(),
                         [&](const std::pair<double, std::uint32_t>& n) { return n.first > keep; }),
                     near.end());
          std::sort(near.begin(), near.end());
          const double step = keep / 255.0;
          binStep_.push_back(step);
          for (const auto& [d, c] : near) {
            if (segments_.size() >= (1u << 24))
              throw std::invalid_argument("a periodic network of over 16 million segments");
            if (kept[c] < 0) {
              kept[c] = std::int64_t(segments_.size());
              Segment k{};
              for (int a = 0; a < 3; ++a) {
                k.a[a] = copies[c].a[a];
                k.e[a] = copies[c].b[a] - copies[c].a[a];
              }
              const double l2 = k.e[0] * k.e[0] + k.e[1] * k.e[1] + k.e[2] * k.e[2];
              k.inverseLength2 = l2 > 0.0 ? 1.0 / l2 : 0.0;
              segments_.push_back(k);
            }
            int q = std::min(int(d / step), 255);
            while (q > 0 && q * step > d) --q;
            candidates_.push_back(Candidate(kept[c]) << 8 | Candidate(q));
          }
          break;
        }
        binStart_.push_back(std::uint32_t(candidates_.size()));
      }
  farthest_ = repeated ? farthest_ * (1.0 + 1e-9) : std::numeric_limits<double>::infinity();
  if (!repeated) {
    std::vector<StrutPiece>().swap(tile_);  // (its bins keep what they need)
    exact_ = exactWithin;
    cap_ = exactWithin - 0.5 * blend;
  }
}

PeriodicSegmentsField::Located PeriodicSegmentsField::locate(double x, double y, double z) const {
  const double p[3] = {x, y, z};
  Located at{};
  double r2 = 0.0;
  int bin[3];
  for (int a = 0; a < 3; ++a) {
    const double u = p[a] - origin_[a];
    // in [0, period] (rounding); unrepeated, the point itself in its nearest bin
    const double w = repeated_ ? u - period_[a] * std::floor(u / period_[a]) : u;
    bin[a] = std::min(std::max(int(std::floor(w / binSize_[a])), 0), bins_[a] - 1);
    at.q[a] = w + origin_[a];
    const double fromCentre = w - (bin[a] + 0.5) * binSize_[a];
    r2 += fromCentre * fromCentre;
  }
  at.r = std::sqrt(r2);
  at.bin = (std::size_t(bin[2]) * bins_[1] + bin[1]) * bins_[0] + bin[0];
  return at;
}

double PeriodicSegmentsField::nearest(const Located& at, double offset[3]) const {
  // Squared distances while scanning (a square root only when the nearest so far improves,
  // for the stop test), the offset once for the winner.
  double best = std::numeric_limits<double>::infinity();
  double best2 = best, o[3];
  const Segment* winner = nullptr;
  const double step = binStep_[at.bin];
  for (std::uint32_t c = binStart_[at.bin]; c < binStart_[at.bin + 1]; ++c) {
    const Candidate k = candidates_[c];
    if ((k & 255u) * step - at.r > best) break;  // this and every later one are farther
    const Segment& s = segments_[k >> 8];
    const double d2 = segmentOffset2(at.q, s.a, s.e, s.inverseLength2, o);
    if (d2 < best2) {
      best2 = d2;
      best = std::sqrt(d2);
      winner = &s;
    }
  }
  return winner ? segmentOffset(at.q, winner->a, winner->e, winner->inverseLength2, offset) : best;
}

double PeriodicSegmentsField::value(double x, double y, double z, double gradient[3]) const {
  const Located at = locate(x, y, z);
  double offset[3];
  const double m = nearest(at, offset);
  if (!(m < exact_)) {  // unrepeated, farther than exactWithin from every segment
    if (gradient) gradient[0] = gradient[1] = gradient[2] = 0.0;
    return cap_;
  }
  // The distance grows away from the closest point: its gradient is -offset / d.
  double gm[3] = {0.0, 0.0, 0.0};
  if (m > 0.0)
    for (int a = 0; a < 3; ++a) gm[a] = -offset[a] / m;
  if (blend_ == 0.0) {
    if (gradient)
      for (int a = 0; a < 3; ++a) gradient[a] = gm[a];
    return m;
  }
  // The segments within the blend of the nearest, in any order (the sum is symmetric).
  double s = 0.0, sum[3] = {0.0, 0.0, 0.0}, o[3];
  const double step = binStep_[at.bin];
  for (std::uint32_t c = binStart_[at.bin]; c < binStart_[at.bin + 1]; ++c) {
    const Candidate k = candidates_[c];
    if ((k & 255u) * step - at.r >= m + blend_) break;
    const Segment& seg = segments_[k >> 8];
    const double d = segmentOffset(at.q, seg.a, seg.e, seg.inverseLength2, o);
    const double t = 1.0 - (d - m) / blend_;
    if (t <= 0.0) continue;
    s += t * t;
    if (gradient && d > 0.0)
      for (int a = 0; a < 3; ++a) sum[a] += t * (-o[a] / d - gm[a]);
  }
  const double blended = m - 0.5 * blend_ + 0.5 * blend_ / s;
  if (!(blended < cap_)) {
    if (gradient) gradient[0] = gradient[1] = gradient[2] = 0.0;
    return cap_;
  }
  if (gradient)
    for (int a = 0; a < 3; ++a) gradient[a] = gm[a] + sum[a] / (s * s);
  return blended;
}

double PeriodicSegmentsField::eval(double x, double y, double z) const {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    return std::numeric_limits<double>::quiet_NaN();
  return value(x, y, z, nullptr);
}

Dual PeriodicSegmentsField::evalGradient(const Dual& x, const Dual& y, const Dual& z) const {
  if (!std::isfinite(x.v) || !std::isfinite(y.v) || !std::isfinite(z.v))
    return Dual(std::numeric_limits<double>::quiet_NaN());
  double g[3];
  const double d = value(x.v, y.v, z.v, g);
  return composed(d, g, x, y, z);
}

Interval PeriodicSegmentsField::evalInterval(const Interval& x, const Interval& y,
                                             const Interval& z) const {
  const Interval* box[3] = {&x, &y, &z};
  double centre[3], half2 = 0.0, largest = 0.0;
  for (int a = 0; a < 3; ++a) {
    const Interval& iv = *box[a];
    if (iv.nan || !std::isfinite(iv.lo) || !std::isfinite(iv.hi)) return {0.0, farthest_, true};
    centre[a] = 0.5 * (iv.lo + iv.hi);
    const double w = 0.5 * (iv.hi - iv.lo);
    half2 += w * w;
    largest = std::max({largest, std::abs(iv.lo), std::abs(iv.hi), period_[a]});
  }
  // The nearest distance moves by at most the point's move (1-Lipschitz), and the blend lowers
  // it by at most blend / 2; the margin covers the rounding of the values at the centre and at
  // the box's points (a few ulps of the coordinates, the period and the blend).
  const double half = std::sqrt(half2) * (1.0 + 1e-12);
  const double least = -0.5 * blend_ * (1.0 + 1e-12);
  if (half >= farthest_) return {least, farthest_};
  double offset[3];
  const double v = nearest(locate(centre[0], centre[1], centre[2]), offset);
  const double margin = 1e-12 * (v + half + blend_) + 1e-13 * largest;
  // Unrepeated, the distance is capped: at least exact_ at the centre where v is (and at most
  // cap_ anywhere); repeated, both are infinite.
  const double m = std::min(v, exact_);
  return {std::min(std::max(least, m - half - 0.5 * blend_ - margin), cap_),
          v < exact_ ? std::min({farthest_, v + half + margin, cap_}) : cap_};
}

std::vector<StrutPiece> PeriodicSegmentsField::segmentsInBox(const Box3& box) const {
  std::vector<StrutPiece> out;
  for (const StrutPiece& s : tile_) {
    int from[3], to[3];
    for (int a = 0; a < 3; ++a) {
      const double lo = std::min(s.a[a], s.b[a]), hi = std::max(s.a[a], s.b[a]);
      from[a] = int(std::ceil((box.lo[a] - hi) / period_[a]));
      to[a] = int(std::floor((box.hi[a] - lo) / period_[a]));
    }
    for (int i = from[0]; i <= to[0]; ++i)
      for (int j = from[1]; j <= to[1]; ++j)
        for (int k = from[2]; k <= to[2]; ++k) {
          const Vec3 shift{i * period_[0], j * period_[1], k * period_[2]};
          out.push_back({vadd(s.a, shift), vadd(s.b, shift)});
        }
  }
  return out;
}

std::size_t PeriodicSegmentsField::memoryBytes() const {
  return sizeof(*this) + tile_.size() * sizeof(StrutPiece) + segments_.size() * sizeof(Segment) +
         binStart_.size() * sizeof(std::uint32_t) + candidates_.size() * sizeof(Candidate) +
         binStep_.size() * sizeof(double);
}

PeriodicNetworkField::PeriodicNetworkField(const std::vector<StrutPiece>& edges,
                                           const std::vector<Vec3>& nodes, const Vec3& period,
                                           const Vec3& origin, const std::array<int, 3>& bins,
                                           double blend)
    : PeriodicSegmentsField(edges, period, origin, bins, blend),
      period_(period),
      origin_(origin),
      bins_(bins) {
  for (const Vec3& n : nodes) nodePoints_.push_back({n, n});
}

std::shared_ptr<const PeriodicSegmentsField> PeriodicNetworkField::nodes() const {
  std::call_once(nodesMade_, [&] {
    nodes_ = std::make_shared<PeriodicSegmentsField>(nodePoints_, period_, origin_, bins_);
  });
  return nodes_;
}

}  // namespace frep

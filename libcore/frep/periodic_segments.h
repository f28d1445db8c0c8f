// The distance to a periodic network of segments given by one tile's segments (a Voronoi
// foam's edges, or its vertices as segments of length 0): the nearest of the tile's segments
// and their copies by the period. The tile is cut into bins; each bin keeps only the copies
// that can be nearest to some point in it, so a point meets a few dozen segments whatever the
// tile holds and the field's memory does not grow with the lattice's extent.
//
// Unrepeated, the same field holds one finite set of segments (a strut lattice's struts mapped
// straight through a deformation): the bins then cover a box round them, and each keeps only
// the segments that can be nearest to a point of it within a given distance E, so that a bin
// in empty space costs little. The field is then min(distance, E) (less half the blend): exact
// within E of a segment, E beyond, so still 1-Lipschitz and its intervals still rigorous.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "frep/field.h"
#include "frep/strut_cells.h"

namespace frep {

class PeriodicSegmentsField : public Field {
 public:
  // `segments` have their middle in the tile [origin, origin + period); every copy
  // of them moved by integer multiples of `period` belongs to the network. `bins` per axis
  // >= 1. Throws std::invalid_argument when the period is too short for the segments (the
  // distance anywhere must be found among the copies in the tiles next to the point's).
  // `blend` > 0 rounds the joints: the distance d is then the smooth minimum of the
  // segments' distances d_i,
  //   d = m - blend / 2 + blend / (2 s),  m = min d_i,  s = sum of max(0, 1 - (d_i - m) / blend)^2,
  // symmetric in the segments (so continuous across the bins), exactly m where every other
  // segment is at least `blend` farther, and never below m - blend / 2.
  PeriodicSegmentsField(const std::vector<StrutPiece>& segments, const Vec3& period,
                        const Vec3& origin, const std::array<int, 3>& bins, double blend = 0.0);

  // The segments once, not repeated: the bins cut `box`; the distance is min(its own,
  // exactWithin) less half the blend at every point of the box, and everywhere when the box
  // holds every segment grown by exactWithin (segments outside the box count all the same).
  static std::shared_ptr<const PeriodicSegmentsField> unrepeated(
      const std::vector<StrutPiece>& segments, const Box3& box, const std::array<int, 3>& bins,
      double exactWithin, double blend = 0.0);

  // The distance to the nearest segment of the network, smoothed by the blend (NaN where a
  // coordinate is).
  double eval(double x, double y, double z) const override;
  Interval evalInterval(const Interval& x, const Interval& y, const Interval& z) const override;
  Dual evalGradient(const Dual& x, const Dual& y, const Dual& z) const override;
  using Field::evalGradient;

  // Every copy of the tile's segments whose box meets `box`, each once (what a beam lattice
  // file lists; none when unrepeated).
  std::vector<StrutPiece> segmentsInBox(const Box3& box) const;
  std::size_t memoryBytes() const;
  std::size_t tileSegmentCount() const { return tile_.size(); }

 private:
  PeriodicSegmentsField(const std::vector<StrutPiece>& segments, const Vec3& size,
                        const Vec3& origin, const std::array<int, 3>& bins, double blend,
                        bool repeated, double exactWithin);
  struct Segment {
    double a[3], e[3];
    double inverseLength2;  // 0 for a point
  };
  // A segment that may be nearest somewhere in a bin (its index, shifted up 8 bits) and its
  // distance from the bin's centre rounded down to a multiple of the bin's step (the low 8
  // bits): a point r from the centre is at least that distance - r from the segment, so a
  // bin's candidates, in order of that distance, stop once it passes the nearest so far.
  using Candidate = std::uint32_t;
  struct Located {
    double q[3];  // the point moved into the tile
    double r;     // its distance from its bin's centre
    std::size_t bin;
  };
  Located locate(double x, double y, double z) const;
  // The nearest segment's distance and its offset from the point (closest point - point).
  double nearest(const Located& at, double offset[3]) const;
  // The field's value, and its gradient when asked.
  double value(double x, double y, double z, double gradient[3]) const;

  std::vector<StrutPiece> tile_;
  Vec3 period_, origin_;
  std::array<int, 3> bins_;
  Vec3 binSize_;
  std::vector<Segment> segments_;        // the copies some bin needs
  std::vector<std::uint32_t> binStart_;  // candidates of bin i: [binStart_[i], binStart_[i+1])
  std::vector<Candidate> candidates_;
  std::vector<double> binStep_;  // the unit of the candidates' distances in each bin
  double farthest_ = 0.0;        // an upper bound of the distance anywhere (repeated)
  double blend_ = 0.0;
  bool repeated_ = true;
  // Unrepeated: the distance is min(the blended distance, cap_), exact where the nearest
  // segment is within exact_ (infinite when repeated).
  double exact_ = std::numeric_limits<double>::infinity();
  double cap_ = std::numeric_limits<double>::infinity();
};

// A strut network's edges and its nodes (where edges meet), both periodic: what the
// voronoi_foam node's loader returns (its nodes through `nodes`).
class PeriodicNetworkField : public PeriodicSegmentsField {
 public:
  // `blend` rounds the joints between edges (not the nodes' spheres).
  PeriodicNetworkField(const std::vector<StrutPiece>& edges, const std::vector<Vec3>& nodes,
                       const Vec3& period, const Vec3& origin, const std::array<int, 3>& bins,
                       double blend = 0.0);
  // Made when first asked (a foam without node spheres never needs it).
  std::shared_ptr<const PeriodicSegmentsField> nodes() const;

 private:
  std::vector<StrutPiece> nodePoints_;
  Vec3 period_, origin_;
  std::array<int, 3> bins_;
  mutable std::once_flag nodesMade_;
  mutable std::shared_ptr<const PeriodicSegmentsField> nodes_;
};

}  // namespace frep

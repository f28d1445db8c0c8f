// Straight struts of cells that follow a cylinder or a sphere (strut_lattice's conform with
// struts = straight): each strut runs straight from the image of one end to the image of the
// other (a chord of the curved strut), so the cells follow the part while every strut stays a
// straight beam.
//
// The lattice is periodic round the axis (a turn holds whole cells) and, on a cylinder, along
// it: a point is turned (and moved along the axis) by whole cells into one wedge, and meets
// the chords of its layer there (on a cylinder the cells at its distance from the axis, on a
// sphere at its distance from the centre and its latitude), filed in bins as an unrepeated
// PeriodicSegmentsField. A layer is made the first time a point asks for it, so the field's
// memory grows with the layers a part reaches, not with its cells.
//
// The distance is exact within `exactWithin` of a chord and capped there (min(distance, E)):
// 1-Lipschitz, so its intervals are rigorous, and no surface lies that far from the struts.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <unordered_map>
#include <vector>

#include "base/vec.h"
#include "frep/field.h"
#include "frep/strut_cells.h"

namespace frep {

class PeriodicSegmentsField;

struct ConformalCells {
  const UnitCell* cell = nullptr;
  Vec3 size{1, 1, 1};    // the cell's sides: out from the axis or centre, round it, along it
  Vec3 origin{0, 0, 0};  // a point of the axis (cylinder), the centre (sphere)
  Vec3 axis{0, 0, 1};
  bool sphere = false;
  int around = 12;  // cells a turn
  double blend = 0.0;
};

// Where the distance is exact: half the cell's shortest side and the blend (a strut thicker
// than that fills its cell), or twice the radius or the node radius where those are larger.
double conformalExactWithin(const Vec3& size, double blend, double radius, double nodeRadius);

// About how many struts the largest layer gathers (one next to the axis or a pole: a whole
// turn of cells): what the strut_lattice's check compares with kMostLayerStruts.
double largestLayerStruts(const ConformalCells& cells, double exactWithin);
constexpr double kMostLayerStruts = 5e5;

class ConformalChordsField final : public Field {
 public:
  // nodes: the distance to the nodes' images instead of the chords.
  ConformalChordsField(const ConformalCells& cells, double exactWithin, bool nodes);

  double eval(double x, double y, double z) const override;
  Interval evalInterval(const Interval& x, const Interval& y, const Interval& z) const override;
  Dual evalGradient(const Dual& x, const Dual& y, const Dual& z) const override;
  using Field::evalGradient;

  // The world point of lattice coordinates q (distance out, arc round, height or arc from the
  // pole), as the curved struts' field reads them.
  Vec3 toWorld(const Vec3& q) const;
  // The chords (or nodes) of every strut of the cells whose lattice coordinates meet `box`,
  // each strut cut where it leaves the lattice's domain (at the axis; at the poles).
  std::vector<StrutPiece> chordsIn(const Box3& box) const;
  std::size_t layersMade() const;

 private:
  struct Folded {
    Vec3 q;             // the point turned (and moved) into its wedge, in the frame's axes
    double turn = 0.0;  // the angle it was turned by
    long long layer = 0;
    bool far = false;  // beyond the layers (at the cap)
  };
  Folded fold(const Vec3& p) const;
  const PeriodicSegmentsField* layer(long long key) const;      // null: no chord within reach
  const PeriodicSegmentsField* madeLayer(long long key) const;  // (made the first time)
  // The distance (capped) and its gradient in the world.
  double value(const Vec3& p, double gradient[3]) const;

  ConformalCells cells_;
  Vec3 u_, v_, w_;                      // the frame: w along the axis
  double alongY_ = 1.0, alongZ_ = 1.0;  // arc per radian round the axis and from the pole
  double wedge_ = 1.0;                  // one cell's angle round the axis
  double exact_ = 1.0, cap_ = 1.0;
  bool nodes_ = false;
  std::uint64_t id_ = 0;  // this field's number among all made (for a thread's last layer)
  mutable std::shared_mutex mutex_;
  mutable std::unordered_map<long long, std::shared_ptr<const PeriodicSegmentsField>> layers_;
};

}  // namespace frep

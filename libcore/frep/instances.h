// Copies of one solid at many points: the data behind the instancer's `instances` instruction.
// A point evaluates only the copies whose reach holds it, found with a k-d tree (nanoflann),
// so 10,000 copies cost a few evaluations of the copied solid, not 10,000.
//
// F(p) = combine over i in N(p) of f(R_i^T (p - c_i)) (R_i: the copy's rotation about the
// input's origin, identity when none is given), where N(p) is the copies within `reach` of p
// (beyond its reach a copy's field is negative: reach is the radius of the ball round the
// solid's origin holding its bounding box) or, where there is none, the nearest copy alone.
// So F is the exact union or blend wherever any copy is within reach, and the nearest copy's
// (negative) field elsewhere.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "base/vec.h"
#include "frep/dual.h"
#include "frep/field.h"
#include "frep/interval.h"

namespace frep {

class Program;

// A Field: the instancer compiles to one `external` instruction holding it.
class InstanceSet final : public Field, public std::enable_shared_from_this<InstanceSet> {
 public:
  // union: max of the copies; blend: the largest two, m1 >= m2, as Pasko's blend union,
  // m1 + a0 / (1 + (m1/a1)^2 + (m2/a1)^2) (exactly the union where only one copy reaches);
  // sum: the sum of the copies within reach, in index order, 0 where none reaches (the blob
  // kernels: a copy's field is >= 0 and exactly 0 beyond its reach, so the sum equals the
  // sum over every copy, or, for a truncated kernel, negligible beyond it).
  enum class Combine { Union, Blend, Sum };
  struct Blend {
    double a0 = 0.0;  // displacement: how much material the blend adds
    double a1 = 1.0;  // range: how far from each copy the blend reaches
  };

  // rotations: empty, or one row-major 3x3 rotation matrix per position.
  InstanceSet(std::vector<Vec3> positions, std::vector<std::array<double, 9>> rotations,
              std::shared_ptr<const Program> copy, double reach, Combine combine, Blend blend);
  ~InstanceSet();
  InstanceSet(const InstanceSet&) = delete;
  InstanceSet& operator=(const InstanceSet&) = delete;

  double eval(double x, double y, double z) const override;
  // Bit-identical to eval() at each point.
  void evalBatch(const double* x, const double* y, const double* z, std::size_t n,
                 double* out) const override;
  Interval evalInterval(const Interval& x, const Interval& y, const Interval& z) const override;
  // x, y, z carry their derivatives (the instancer may sit under a transform).
  Dual evalGradient(const Dual& x, const Dual& y, const Dual& z) const override;
  using Field::evalGradient;
  void evalGradientBatch(const Dual* x, const Dual* y, const Dual* z, std::size_t n,
                         Dual* out) const override;
  // The copies within reach of the box, in the same order, so every mode gives the same
  // values there; a point of the box that no copy reaches is evaluated by the whole set (its
  // nearest copy), and so are intervals. nullptr when that is every copy.
  std::shared_ptr<const Field> specialise(const Box3& box) const override;
  Box3 bounds() const override;

  std::size_t size() const { return positions_.size(); }

  // The (point, copy) pairs of a batch (scratch for the batch modes): point j's pairs are
  // start[j] .. start[j + 1]; the arrays may be longer than start.back() (kept between
  // batches, so they are not zeroed for each).
  struct PairBatch {
    std::vector<std::uint32_t> ids, copies;
    std::vector<std::size_t> start;
    std::vector<double> qx, qy, qz;
  };
  double reach() const { return reach_; }

 private:
  template <class At>
  std::size_t gatherPairs(std::size_t n, At at, PairBatch& pairs) const;
  // evalBatch and evalGradientBatch of the first points of a batch; return how many.
  std::size_t evalBatchPart(const double* x, const double* y, const double* z, std::size_t n,
                            double* out) const;
  std::size_t evalGradientBatchPart(const Dual* x, const Dual* y, const Dual* z, std::size_t n,
                                    Dual* out) const;
  // The copies N(p), in increasing index order (so every mode combines them alike).
  void near(double x, double y, double z, std::vector<std::uint32_t>& out) const;
  template <class T>
  T combine(const T* values, std::size_t n) const;
  // evalInterval of a sum (Combine::Sum) over the box with centre c and half-diagonal h.
  Interval sumInterval(const Interval box[3], const double c[3], double h) const;
  Dual toWorld(std::uint32_t i, const Dual& g, const Dual& x, const Dual& y, const Dual& z) const;
  // The point in copy i's own coordinates: R_i^T (p - c_i).
  template <class T>
  void local(std::uint32_t i, const T& x, const T& y, const T& z, T q[3]) const;

  struct Index;
  std::vector<Vec3> positions_;
  std::vector<std::array<double, 9>> rotations_;
  std::shared_ptr<const Program> copy_;
  double reach_;
  Combine combine_;
  Blend blend_;
  std::unique_ptr<Index> index_;
  // A specialised subset's whole set: it answers points no copy of the subset reaches, and
  // intervals. Null for the whole set itself.
  std::shared_ptr<const InstanceSet> whole_;
};

}  // namespace frep

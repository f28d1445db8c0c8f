// FfdField: the pull-back of a field through an FFD lattice (see ffd_field.h).
#include "frep/ffd_field.h"

#include <algorithm>
#include <cmath>

#include "lattice/ffd_map.h"

namespace frep {

namespace {

Box3 boxOf(const Interval& x, const Interval& y, const Interval& z) {
  return {{x.lo, y.lo, z.lo}, {x.hi, y.hi, z.hi}};
}

// min(f, -eps), as eval computes it (f < -eps ? f : -eps; NaN gives -eps).
double vacated(double f, double eps) {
  return f < -eps ? f : -eps;
}
Interval vacated(const Interval& f, double eps) {
  return {std::min(f.lo, -eps), f.nan ? -eps : std::min(f.hi, -eps), false};
}

}  // namespace

FfdField::FfdField(std::shared_ptr<const Field> input, std::shared_ptr<const FfdMap> map,
                   std::shared_ptr<const std::vector<int>> leaves)
    : input_(std::move(input)),
      map_(std::move(map)),
      leaves_(std::move(leaves)),
      eps_(1e-9 * map_->lattice().scale()) {}

double FfdField::eval(double x, double y, double z) const {
  if (auto s = map_->inverse({x, y, z}, leaves_.get())) {
    const Vec3 q = map_->lattice().restPoint(*s);
    return input_->eval(q[0], q[1], q[2]);
  }
  const double f = input_->eval(x, y, z);
  return boxHolds(map_->lattice().rest(), {x, y, z}) ? vacated(f, eps_) : f;
}

Interval FfdField::evalInterval(const Interval& x, const Interval& y, const Interval& z) const {
  const Box3 box = boxOf(x, y, z);
  const FfdMap::BoxCover c = map_->cover(box, leaves_.get());
  Interval out;
  bool any = false;
  if (c.cover != FfdMap::Cover::Outside) {
    // restPoint is monotone in each coordinate, rounding included: the rest points of the
    // preimage box's corners bound those of its points.
    const Vec3 lo = map_->lattice().restPoint(c.preimage.lo),
               hi = map_->lattice().restPoint(c.preimage.hi);
    out = input_->evalInterval({lo[0], hi[0]}, {lo[1], hi[1]}, {lo[2], hi[2]});
    any = true;
  }
  if (c.cover != FfdMap::Cover::Inside) {
    const Box3& rest = map_->lattice().rest();
    const Interval f = input_->evalInterval(x, y, z);
    Interval outside;
    if (!boxesMeet(box, rest))
      outside = f;
    else if (boxWithin(box, rest))
      outside = vacated(f, eps_);
    else
      outside = hull(f, vacated(f, eps_));
    out = any ? hull(out, outside) : outside;
  }
  return out;
}

Dual FfdField::evalGradient(const Dual& x, const Dual& y, const Dual& z) const {
  if (auto s = map_->inverse({x.v, y.v, z.v}, leaves_.get())) {
    const FfdLattice& lattice = map_->lattice();
    const Vec3 q = lattice.restPoint(*s);
    Mat3 j, inv;
    lattice.forward(*s, &j);
    Dual qd[3] = {Dual(q[0]), Dual(q[1]), Dual(q[2])};
    if (invert(j, &inv)) {
      // dq/dp = diag(rest size) J^-1, composed with the derivatives p carries.
      const Dual* p[3] = {&x, &y, &z};
      for (int a = 0; a < 3; ++a) {
        const double size = lattice.rest().hi[a] - lattice.rest().lo[a];
        for (int k = 0; k < 3; ++k) {
          double d = 0.0;
          for (int b = 0; b < 3; ++b) d += inv[a][b] * p[b]->d[k];
          qd[a].d[k] = size * d;
        }
      }
    }
    return input_->evalGradient(qd[0], qd[1], qd[2]);
  }
  const Dual f = input_->evalGradient(x, y, z);
  if (!boxHolds(map_->lattice().rest(), {x.v, y.v, z.v})) return f;
  return f.v < -eps_ ? f : Dual(-eps_);
}

std::shared_ptr<const Field> FfdField::specialise(const Box3& box) const {
  auto leaves = std::make_shared<std::vector<int>>();
  const std::vector<int> meeting = map_->leavesMeeting(box);
  if (leaves_) {
    std::set_intersection(meeting.begin(), meeting.end(), leaves_->begin(), leaves_->end(),
                          std::back_inserter(*leaves));
  } else {
    *leaves = meeting;
  }
  // The input is asked about points of the box (outside the lattice) and rest points of the
  // leaves that reach it.
  Box3 inputBox = box;
  if (!leaves->empty()) {
    Box3 stu = map_->leafParameters((*leaves)[0]);
    for (int id : *leaves) stu = boxHull(stu, map_->leafParameters(id));
    const FfdLattice& lattice = map_->lattice();
    inputBox = boxHull(inputBox, Box3{lattice.restPoint(stu.lo), lattice.restPoint(stu.hi)});
  }
  std::shared_ptr<const Field> input = input_->specialise(inputBox);
  const bool sameLeaves =
      leaves_ ? leaves->size() == leaves_->size() : leaves->size() == map_->leafCount();
  if (!input && sameLeaves) return nullptr;
  return std::make_shared<FfdField>(input ? input : input_, map_, std::move(leaves));
}

Box3 FfdField::bounds() const {
  return deformedBounds(*map_, input_->bounds());
}

Box3 deformedBounds(const FfdMap& map, const Box3& in) {
  const Box3& rest = map.lattice().rest();
  const Box3 image = map.imageOf(in);
  const bool imaged = image.lo[0] <= image.hi[0];
  if (boxWithin(in, rest)) return imaged ? image : in;
  return imaged ? boxHull(image, in) : in;
}

}  // namespace frep

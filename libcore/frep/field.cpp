#include "frep/field.h"

#include <algorithm>

#include <limits>

namespace frep {

void Field::evalBatch(const double* x, const double* y, const double* z, std::size_t n,
                      double* out) const {
  for (std::size_t i = 0; i < n; ++i) out[i] = eval(x[i], y[i], z[i]);
}

void Field::evalGradientBatch(const Dual* x, const Dual* y, const Dual* z, std::size_t n,
                              Dual* out) const {
  for (std::size_t i = 0; i < n; ++i) out[i] = evalGradient(x[i], y[i], z[i]);
}

std::shared_ptr<const Field> Field::specialise(const Box3&) const { return nullptr; }

Box3 Field::bounds() const {
  const double inf = std::numeric_limits<double>::infinity();
  return {{-inf, -inf, -inf}, {inf, inf, inf}};
}

const Field& specialiseInto(const Field& field, const Box3& box,
                            std::shared_ptr<const Field>& holder) {
  std::shared_ptr<const Field> s = field.specialise(box);
  if (!s) return field;
  holder = std::move(s);
  return *holder;
}

Dual cappedByBox(const Dual& f, const Box3& box, const Vec3& p) {
  const double d[6] = {p[0] - box.lo[0], box.hi[0] - p[0], p[1] - box.lo[1],
                       box.hi[1] - p[1], p[2] - box.lo[2], box.hi[2] - p[2]};
  const int face = static_cast<int>(std::min_element(d, d + 6) - d);
  if (!(d[face] < f.v)) return f;
  Dual cap(d[face], 0, 0, 0);
  cap.d[face / 2] = face % 2 ? -1.0 : 1.0;
  return cap;
}

}  // namespace frep

#include "frep/bounds.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <vector>

#include "frep/interval.h"

namespace frep {

bool SolidBounds::bounded() const {
  if (empty) return false;
  for (const auto& axis : unbounded)
    if (axis[0] || axis[1]) return false;
  return true;
}

namespace {

constexpr double kAspect = 8.0;

struct Cell {
  Box3 box;
  double priority;  // how far the cell reaches in the searched direction
  int depth;
};

struct CellOrder {
  // Furthest first; among equals the deepest, so the search dives instead of spreading.
  bool operator()(const Cell& a, const Cell& b) const {
    if (a.priority != b.priority) return a.priority < b.priority;
    return a.depth < b.depth;
  }
};

bool mayBeInside(const Program& p, const Box3& b) {
  Interval v = p.evalInterval(Interval(b.lo[0], b.hi[0]), Interval(b.lo[1], b.hi[1]),
                              Interval(b.lo[2], b.hi[2]));
  // NaN upper bounds (0/0 and the like over a huge cell) must not prune.
  return !(v.hi < 0.0);
}

// Returns the extent of the solid along `axis` in direction `sign` (+1: max, -1: min), or
// nothing when every cell is proven outside.
bool extremeAlong(const Program& p, const BoundsOptions& o, int axis, int sign, double* out) {
  auto reach = [&](const Box3& b) { return sign > 0 ? b.hi[axis] : -b.lo[axis]; };
  std::priority_queue<Cell, std::vector<Cell>, CellOrder> queue;
  queue.push({o.search, reach(o.search), 0});
  std::size_t evaluations = 0;
  while (!queue.empty()) {
    Cell c = queue.top();
    if (evaluations >= o.maxEvaluations) break;  // c.priority bounds every remaining cell
    queue.pop();
    ++evaluations;
    if (!mayBeInside(p, c.box)) continue;
    if (c.box.hi[axis] - c.box.lo[axis] <= o.tolerance) {  // it reaches furthest of all
      *out = sign > 0 ? c.box.hi[axis] : c.box.lo[axis];
      return true;
    }
    // Shrink first: bisect for the deepest cut such that the outer slab of the cell is
    // provably empty, and drop that slab. Exact in a few evaluations for faces across the
    // direction (even unbounded ones, where splitting sideways would never end).
    bool shrunk = false;
    {
      double keep = sign > 0 ? c.box.lo[axis] : c.box.hi[axis];  // slab from here: not empty
      double cut = sign > 0 ? c.box.hi[axis] : c.box.lo[axis];   // slab from here: empty
      while (std::abs(cut - keep) > o.tolerance && evaluations < o.maxEvaluations) {
        const double t = 0.5 * (keep + cut);
        Box3 slab = c.box;
        (sign > 0 ? slab.lo : slab.hi)[axis] = t;
        ++evaluations;
        (mayBeInside(p, slab) ? keep : cut) = t;
      }
      double& side = sign > 0 ? c.box.hi[axis] : c.box.lo[axis];
      if (cut != side) {
        side = cut;
        shrunk = true;
      }
    }
    if (shrunk) {  // other cells may now reach further: back into the queue
      queue.push({c.box, reach(c.box), c.depth});
      continue;
    }
    // Then split: the searched axis while the cell is at most kAspect times wider across it,
    // else the longest side. Flat cells mean fewer cells to rule out along a face across the
    // search direction; bounded flatness keeps the intervals over them tight.
    int split = axis;
    for (int k = 0; k < 3; ++k)
      if (c.box.hi[k] - c.box.lo[k] > kAspect * (c.box.hi[split] - c.box.lo[split])) split = k;
    double mid = 0.5 * (c.box.lo[split] + c.box.hi[split]);
    Box3 a = c.box, b = c.box;
    a.hi[split] = mid;
    b.lo[split] = mid;
    queue.push({a, reach(a), c.depth + 1});
    queue.push({b, reach(b), c.depth + 1});
  }
  if (queue.empty()) return false;
  double r = queue.top().priority;
  *out = sign > 0 ? r : -r;
  return true;
}

}  // namespace

SolidBounds findBounds(const Program& program, const BoundsOptions& options) {
  SolidBounds result;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      int sign = side == 0 ? -1 : 1;
      double v = 0.0;
      if (!extremeAlong(program, options, axis, sign, &v)) {
        result.empty = true;
        result.box = Box3{};
        return result;
      }
      double limit = side == 0 ? options.search.lo[axis] : options.search.hi[axis];
      if (std::abs(v - limit) <= options.tolerance) {
        result.unbounded[axis][side] = true;
        v = limit;
      }
      (side == 0 ? result.box.lo : result.box.hi)[axis] = v;
    }
  }
  return result;
}

}  // namespace frep

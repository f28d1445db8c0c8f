#include "frep/bounds.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <vector>

#include "frep/interval.h"
#include "frep/program.h"

namespace frep {

bool SolidBounds::bounded() const {
  if (empty) return false;
  for (const auto& axis : unbounded)
    if (axis[0] || axis[1]) return false;
  return true;
}

namespace {

constexpr double kAspect = 8.0;
constexpr int kBisectionSteps = 6;
constexpr double kCoarseCellsPerSpan = 4.0;
constexpr std::size_t kMaxCoarseCells = 4096;
// Instructions interval-evaluated per side (and for the coarse cells) at most: a program of
// two million instructions (100,000 swept segments) gets 16 evaluations a side, so its box
// is looser rather than minutes away. Programs of up to 1,000 instructions keep every
// evaluation asked for; a search rarely needs them all.
constexpr double kInstructionsPerSide = 2e7;
constexpr std::size_t kFewestEvaluations = 16;
// A cell thinner than the tolerance across the searched direction is split sideways down to
// this fraction of the cells' span before its far side is taken as the extent.
constexpr double kFinestCellsPerSpan = 16.0;

struct Cell {
  Box3 box;
  double priority;  // how far the cell reaches in the searched direction
  int depth;
  // Coordinate along the searched axis from which the outer slab is not known to be empty:
  // where the last bisection stopped, so a revisit after shrinking goes on from there.
  double keep;
};

struct CellOrder {
  // Furthest first; among equals the deepest, so the search dives instead of spreading.
  bool operator()(const Cell& a, const Cell& b) const {
    if (a.priority != b.priority) return a.priority < b.priority;
    return a.depth < b.depth;
  }
};

bool mayBeInside(const Field& p, const Box3& b) {
  Interval v = p.evalInterval(Interval(b.lo[0], b.hi[0]), Interval(b.lo[1], b.hi[1]),
                              Interval(b.lo[2], b.hi[2]));
  // NaN upper bounds (0/0 and the like over a huge cell) must not prune.
  return !(v.hi < 0.0);
}

// The deepest coordinate along `axis` (towards `sign`) beyond which the span of the cells is
// provably empty, to within the tolerance; the span's own far side where nothing is proven.
double spanCut(const Field& p, const BoundsOptions& o, const std::vector<Box3>& cells, int axis,
               int sign, std::size_t* evaluations, double* finest) {
  if (cells.empty()) return 0.0;
  Box3 span = cells[0];
  for (const Box3& c : cells)
    for (int a = 0; a < 3; ++a) {
      span.lo[a] = std::min(span.lo[a], c.lo[a]);
      span.hi[a] = std::max(span.hi[a], c.hi[a]);
    }
  for (int a = 0; a < 3; ++a)
    *finest = std::max(*finest, (span.hi[a] - span.lo[a]) / kFinestCellsPerSpan);
  double keep = sign > 0 ? span.lo[axis] : span.hi[axis];  // slab from here: not empty
  double cut = sign > 0 ? span.hi[axis] : span.lo[axis];   // slab from here: empty
  while (std::abs(cut - keep) > o.tolerance && *evaluations < o.maxEvaluations) {
    const double t = 0.5 * (keep + cut);
    Box3 slab = span;
    (sign > 0 ? slab.lo : slab.hi)[axis] = t;
    ++*evaluations;
    (mayBeInside(p, slab) ? keep : cut) = t;
  }
  return cut;
}

// Returns the extent of the solid along `axis` in direction `sign` (+1: max, -1: min), or
// nothing when every cell is proven outside.
bool extremeAlong(const Field& p, const BoundsOptions& o, const std::vector<Box3>& start, int axis,
                  int sign, double* out) {
  auto reach = [&](const Box3& b) { return sign > 0 ? b.hi[axis] : -b.lo[axis]; };
  std::priority_queue<Cell, std::vector<Cell>, CellOrder> queue;
  auto inner = [&](const Box3& b) { return sign > 0 ? b.lo[axis] : b.hi[axis]; };
  std::size_t evaluations = 0;
  // One cut across all the start cells first: the deepest slab of their whole span that is
  // provably empty. A face across the direction (a box's, a half-space's) or a round far side
  // is found in a few evaluations here, where cell by cell every cell along the face would
  // have to be shrunk to the tolerance on its own.
  double finest = o.tolerance;  // sideways size of a thin cell whose interval is trusted
  const double cut = spanCut(p, o, start, axis, sign, &evaluations, &finest);
  for (Box3 b : start) {
    if (sign > 0 ? b.lo[axis] >= cut : b.hi[axis] <= cut) continue;
    (sign > 0 ? b.hi : b.lo)[axis] =
        sign > 0 ? std::min(b.hi[axis], cut) : std::max(b.lo[axis], cut);
    queue.push({b, reach(b), 0, inner(b)});
  }
  while (!queue.empty()) {
    Cell c = queue.top();
    if (evaluations >= o.maxEvaluations) break;  // c.priority bounds every remaining cell
    queue.pop();
    ++evaluations;
    if (!mayBeInside(p, c.box)) continue;
    if (c.box.hi[axis] - c.box.lo[axis] <= o.tolerance) {
      // Thin, but wide sideways its interval may be loose (a cell that shrank to its near
      // side): split it sideways until it is small next to the span, then it reaches
      // furthest of all. Along a real face this is one short dive.
      int wide = -1;
      for (int k = 0; k < 3; ++k)
        if (k != axis && c.box.hi[k] - c.box.lo[k] > finest &&
            (wide < 0 || c.box.hi[k] - c.box.lo[k] > c.box.hi[wide] - c.box.lo[wide]))
          wide = k;
      if (wide >= 0) {
        const double mid = 0.5 * (c.box.lo[wide] + c.box.hi[wide]);
        Box3 a = c.box, b = c.box;
        a.hi[wide] = mid;
        b.lo[wide] = mid;
        queue.push({a, reach(a), c.depth + 1, c.keep});
        queue.push({b, reach(b), c.depth + 1, c.keep});
        continue;
      }
      *out = sign > 0 ? c.box.hi[axis] : c.box.lo[axis];
      return true;
    }
    // Shrink first: bisect for the deepest cut such that the outer slab of the cell is
    // provably empty, and drop that slab. Exact in a few evaluations for faces across the
    // direction (even unbounded ones, where splitting sideways would never end).
    bool shrunk = false;
    {
      double keep = c.keep;                                     // slab from here: not empty
      double cut = sign > 0 ? c.box.hi[axis] : c.box.lo[axis];  // slab from here: empty
      // A few steps per visit: any cut found is valid, and a shrunk cell is visited again.
      for (int step = 0; step < kBisectionSteps && std::abs(cut - keep) > o.tolerance &&
                         evaluations < o.maxEvaluations;
           ++step) {
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
      c.keep = keep;
    }
    if (shrunk) {  // other cells may now reach further: back into the queue
      queue.push({c.box, reach(c.box), c.depth, c.keep});
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
    // Smaller cells have tighter intervals: their bisection starts afresh.
    queue.push({a, reach(a), c.depth + 1, inner(a)});
    queue.push({b, reach(b), c.depth + 1, inner(b)});
  }
  if (queue.empty()) return false;
  double r = queue.top().priority;
  *out = sign > 0 ? r : -r;
  return true;
}

// Level by level, splits every cell that may hold part of the solid into eight, until the cells
// are small next to the box they span (or too many). Far cells are ruled out while they are
// about as large as their distance to the solid, which plain interval arithmetic manages; a
// best-first search from the whole search box would need cells far smaller than that.
std::vector<Box3> coarseCells(const Field& p, const BoundsOptions& o) {
  std::vector<Box3> cells;
  if (mayBeInside(p, o.search)) cells.push_back(o.search);
  std::size_t evaluations = 1;
  for (int level = 0; level < 64 && !cells.empty(); ++level) {
    Box3 span = cells[0];
    for (const Box3& c : cells)
      for (int a = 0; a < 3; ++a) {
        span.lo[a] = std::min(span.lo[a], c.lo[a]);
        span.hi[a] = std::max(span.hi[a], c.hi[a]);
      }
    double cellSize = 0.0, spanSize = 0.0;
    for (int a = 0; a < 3; ++a) {
      cellSize = std::max(cellSize, cells[0].hi[a] - cells[0].lo[a]);
      spanSize = std::max(spanSize, span.hi[a] - span.lo[a]);
    }
    if (cellSize * kCoarseCellsPerSpan <= spanSize || cells.size() * 8 > kMaxCoarseCells ||
        evaluations + cells.size() * 8 > o.maxEvaluations || cellSize <= o.tolerance)
      break;
    std::vector<Box3> next;
    for (const Box3& c : cells) {
      const Vec3 mid{0.5 * (c.lo[0] + c.hi[0]), 0.5 * (c.lo[1] + c.hi[1]),
                     0.5 * (c.lo[2] + c.hi[2])};
      for (int k = 0; k < 8; ++k) {
        Box3 child;
        for (int a = 0; a < 3; ++a) {
          const bool high = (k >> a) & 1;
          child.lo[a] = high ? mid[a] : c.lo[a];
          child.hi[a] = high ? c.hi[a] : mid[a];
        }
        ++evaluations;
        if (mayBeInside(p, child)) next.push_back(child);
      }
    }
    cells.swap(next);
  }
  return cells;
}

}  // namespace

SolidBounds findBounds(const Field& program, const BoundsOptions& given) {
  // Search inside the known box, padded so that a solid touching it is still found inside.
  BoundsOptions options = given;
  bool knownSide[3][2] = {};
  for (int a = 0; a < 3; ++a) {
    const double lo = given.known.lo[a], hi = given.known.hi[a];
    const double pad =
        (std::isfinite(lo) && std::isfinite(hi) ? 1e-3 * (hi - lo) : 0.0) + 4 * given.tolerance;
    if (std::isfinite(lo) && lo - pad > options.search.lo[a]) {
      options.search.lo[a] = lo - pad;
      knownSide[a][0] = true;
    }
    if (std::isfinite(hi) && hi + pad < options.search.hi[a]) {
      options.search.hi[a] = hi + pad;
      knownSide[a][1] = true;
    }
  }
  if (const auto* compiled = dynamic_cast<const Program*>(&program)) {
    const double affordable =
        kInstructionsPerSide / static_cast<double>(std::max<std::size_t>(1, compiled->instructionCount()));
    if (affordable < static_cast<double>(options.maxEvaluations))
      options.maxEvaluations = std::max(kFewestEvaluations, static_cast<std::size_t>(affordable));
  }
  SolidBounds result;
  if (!options.search.valid()) {  // the structure says: nothing (an empty intersection)
    result.empty = true;
    return result;
  }
  const std::vector<Box3> start = coarseCells(program, options);
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      int sign = side == 0 ? -1 : 1;
      double v = 0.0;
      if (!extremeAlong(program, options, start, axis, sign, &v)) {
        result.empty = true;
        result.box = Box3{};
        return result;
      }
      double limit = side == 0 ? options.search.lo[axis] : options.search.hi[axis];
      if (std::abs(v - limit) <= options.tolerance) {
        result.unbounded[axis][side] = !knownSide[axis][side];
        v = limit;
      }
      (side == 0 ? result.box.lo : result.box.hi)[axis] = v;
    }
  }
  return result;
}

}  // namespace frep

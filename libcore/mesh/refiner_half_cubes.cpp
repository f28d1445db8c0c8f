// The refiner's half cubes: the half-cell grid's signs (sampled, or virtual from the seam),
// each half cube's lines and loops, fanned, and the roots on its edges.
#include "mesh/refiner.h"

namespace frep {
namespace refinement {

bool Refiner::sampled(const std::int64_t f[3]) const {
  int odd = 0;
  for (int a = 0; a < 3; ++a) odd += static_cast<int>(f[a] & 1);
  if (odd == 0) return true;
  if (odd == 3) return true;
  std::int64_t lo[3];
  for (int a = 0; a < 3; ++a) lo[a] = f[a] / 2;  // odd: the cell; even: the plane
  // cubes round: along an even axis, the cubes below and above the plane
  std::int64_t q[3];
  for (int d = 0; d < 8; ++d) {
    bool skip = false;
    for (int a = 0; a < 3; ++a) {
      const int bit = (d >> a) & 1;
      if (f[a] & 1) {
        if (bit) skip = true;
        q[a] = lo[a];
      } else {
        q[a] = lo[a] - bit;
      }
    }
    if (skip) continue;
    if (!inOmega(q)) return false;
  }
  return true;
}

bool Refiner::virtualSign(const std::int64_t f[3]) const {
  int odd = 0, oddAxis = -1, evenAxis = -1;
  for (int a = 0; a < 3; ++a) {
    if (f[a] & 1) {
      ++odd;
      oddAxis = a;
    } else {
      evenAxis = a;
    }
  }
  if (odd == 1) {  // a grid edge's midpoint: the side of the edge's vertex
    std::int64_t e0[3] = {f[0], f[1], f[2]}, e1[3] = {f[0], f[1], f[2]};
    e0[oddAxis] -= 1;
    e1[oddAxis] += 1;
    const bool s0 = isInside(value(e0)), s1 = isInside(value(e1));
    if (s0 == s1) return s0;
    const std::int64_t l[3] = {f[0] / 2, f[1] / 2, f[2] / 2};
    bool lowerHalf;
    coarseVertex(l, oddAxis, &lowerHalf);
    return lowerHalf ? s1 : s0;
  }
  // a face's centre: from the seam face, or the corners' side where no line crosses it
  std::int64_t cell[3] = {f[0] / 2, f[1] / 2, f[2] / 2};
  const std::uint64_t key =
      g_.linear(cell[0], cell[1], cell[2]) * 3 + static_cast<std::uint64_t>(evenAxis);
  const auto it = seam_.find(key);
  if (it != seam_.end() && !it->second.lines.empty()) {
    if (!it->second.cut) throw Abort("a seam face's centre was asked before it was cut");
    return it->second.centreInside;
  }
  const int b = (evenAxis + 1) % 3, c = (evenAxis + 2) % 3;
  std::int64_t k0[3] = {f[0], f[1], f[2]};
  k0[b] -= 1;
  k0[c] -= 1;
  const bool s = isInside(value(k0));
  for (int d = 1; d < 4; ++d) {
    std::int64_t k[3] = {k0[0], k0[1], k0[2]};
    k[b] += 2 * (d & 1);
    k[c] += 2 * (d >> 1);
    if (isInside(value(k)) != s) throw Abort("a crossed face of the seam has no lines");
  }
  return s;
}

std::vector<std::uint32_t> Refiner::crossings(const std::int64_t f[3], int d) {
  const int b = (d + 1) % 3, c = (d + 2) % 3;
  std::int64_t f1[3] = {f[0], f[1], f[2]};
  f1[d] += 1;
  const bool oddB = f[b] & 1, oddC = f[c] & 1;
  if (!oddB && !oddC) {  // on a grid edge
    if (!sampled(f[d] % 2 ? f : f1)) {
      // virtual: the coarse vertex, where it lies in this half
      std::int64_t e0[3] = {f[0], f[1], f[2]};
      e0[d] = f[d] - (f[d] & 1);
      std::int64_t e2[3] = {e0[0], e0[1], e0[2]};
      e2[d] += 2;
      if (isInside(value(e0)) == isInside(value(e2))) return {};
      const std::int64_t l[3] = {e0[0] / 2, e0[1] / 2, e0[2] / 2};
      bool lowerHalf;
      const std::uint32_t v = coarseVertex(l, d, &lowerHalf);
      if (lowerHalf == ((f[d] & 1) == 0)) return {v};
      return {};
    }
  } else if (oddB != oddC) {                       // on a grid face, along a midline
    const int n = oddB ? c : b, o = oddB ? b : c;  // the face's normal; the odd axis
    std::int64_t cell[3] = {f[0] / 2, f[1] / 2, f[2] / 2};
    std::int64_t below[3] = {cell[0], cell[1], cell[2]};
    below[n] -= 1;
    if (inOmega(below) != inOmega(cell)) {  // a seam face
      const std::uint64_t key =
          g_.linear(cell[0], cell[1], cell[2]) * 3 + static_cast<std::uint64_t>(n);
      const auto it = seam_.find(key);
      if (it == seam_.end()) return {};
      const SeamFace& sf = it->second;
      const int fb = (n + 1) % 3;
      // the midline across o, halves along d
      const int half = (o == fb ? 0 : 2) + static_cast<int>(f[d] & 1);
      std::vector<std::uint32_t> out;
      for (const auto& [x, v] : sf.halfMid[half]) out.push_back(v);
      return out;
    }
  }
  if (fineSign(f) == fineSign(f1)) return {};
  const std::uint64_t key = fineKey(f) * 3 + static_cast<std::uint64_t>(d);
  const auto it = rootVertex_.find(key);
  if (it != rootVertex_.end()) return {it->second};
  const std::uint32_t v = newVertex({0.f, 0.f, 0.f});
  rootVertex_[key] = v;
  roots_.push_back({{f[0], f[1], f[2]}, d, v});
  return {v};
}

void Refiner::meshHalfCubes() {
  // every half cube's lines first (their vertices on the half-cell grid's edges found in
  // one batch), then the cells
  std::vector<Cell> cells;
  std::vector<std::uint64_t> cellCube;
  for (std::uint64_t id : cubes_) {
    std::int64_t c[3];
    cubeOf(id, c);
    try {
      for (int h = 0; h < 8; ++h) {
        const std::int64_t f0[3] = {2 * c[0] + (h & 1), 2 * c[1] + ((h >> 1) & 1),
                                    2 * c[2] + ((h >> 2) & 1)};
        cells.push_back(halfCube(f0));
        cellCube.push_back(id);
      }
    } catch (const Abort&) {
      failed_.cubes.push_back(id);
    }
  }
  throwFailures();
  findRoots();
  std::uint64_t last = UINT64_MAX;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (cellCube[i] == last && !failed_.cubes.empty() && failed_.cubes.back() == last) continue;
    try {
      cells_.meshCell(cells[i], 0);
    } catch (const Abort&) {
      failed_.cubes.push_back(cellCube[i]);
    }
    if (cellCube[i] != last) ++stats_.cubes;
    last = cellCube[i];
  }
  throwFailures();
  cells_.flipCreases();
}

void Refiner::faceLines(const std::int64_t f0[3], int a, int side, std::vector<Seg>* out) {
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  std::int64_t fp[3] = {f0[0], f0[1], f0[2]};
  fp[a] += side;
  if ((fp[a] & 1) == 0) {  // on a grid face: a seam face gives its pieces
    std::int64_t cell[3] = {fp[0] / 2, fp[1] / 2, fp[2] / 2};
    std::int64_t below[3] = {cell[0], cell[1], cell[2]};
    below[a] -= 1;
    if (inOmega(below) != inOmega(cell)) {
      const std::uint64_t key =
          g_.linear(cell[0], cell[1], cell[2]) * 3 + static_cast<std::uint64_t>(a);
      const auto it = seam_.find(key);
      if (it == seam_.end()) return;
      const int quarter = static_cast<int>(fp[b] & 1) + 2 * static_cast<int>(fp[c] & 1);
      for (const Seg& s : it->second.quarter[quarter]) out->push_back(s);
      return;
    }
  }
  // the face's corners counterclockwise seen from outside the half cube
  static const int ccw[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::int64_t corner[4][3];
  for (int k = 0; k < 4; ++k) {
    const int i = side == 1 ? k : (4 - k) % 4;
    for (int x = 0; x < 3; ++x) corner[k][x] = fp[x];
    corner[k][b] += ccw[i][0];
    corner[k][c] += ccw[i][1];
  }
  // walk: corner k, then the crossings on the edge to corner k + 1
  std::vector<WalkStep> walk;
  for (int k = 0; k < 4; ++k) {
    const std::int64_t* p = corner[k];
    const std::int64_t* q = corner[(k + 1) % 4];
    walk.push_back({true, fineSign(p), 0});
    int d = -1;
    for (int x = 0; x < 3; ++x)
      if (p[x] != q[x]) d = x;
    std::int64_t lower[3] = {p[0], p[1], p[2]};
    lower[d] = std::min(p[d], q[d]);
    std::vector<std::uint32_t> xs = crossings(lower, d);
    if (q[d] < p[d]) std::reverse(xs.begin(), xs.end());
    for (std::uint32_t v : xs) walk.push_back({false, false, v});
  }
  double mid[3];
  for (int x = 0; x < 3; ++x)
    mid[x] = 0.5 * (fineCoord(x, corner[0][x]) + fineCoord(x, corner[2][x]));
  cells_.pairCrossings(walk, mid, out);
}

void Refiner::findRoots() {
  const std::size_t n = roots_.size();
  if (n == 0) return;
  std::vector<IllinoisBracket> b(n);
  std::vector<double> t(n, kNoRoot);
  std::vector<char> active(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    std::int64_t f1[3] = {roots_[i].f[0], roots_[i].f[1], roots_[i].f[2]};
    f1[roots_[i].d] += 1;
    b[i].fa = value(roots_[i].f);
    b[i].fb = value(f1);
    active[i] = isInside(b[i].fa) != isInside(b[i].fb);
  }
  std::vector<double> x, y, z, v;
  std::vector<std::size_t> which;
  for (int it = 0; it < kMaxRootSteps; ++it) {
    x.clear();
    y.clear();
    z.clear();
    which.clear();
    for (std::size_t i = 0; i < n; ++i) {
      if (!active[i]) continue;
      const double u = illinoisEstimate(b[i]);
      t[i] = u;
      const Root& r = roots_[i];
      double p[3];
      for (int k = 0; k < 3; ++k) p[k] = fineCoord(k, r.f[k]);
      p[r.d] += u * (fineCoord(r.d, r.f[r.d] + 1) - p[r.d]);
      x.push_back(p[0]);
      y.push_back(p[1]);
      z.push_back(p[2]);
      which.push_back(i);
    }
    if (which.empty()) break;
    v.resize(which.size());
    field_.evalBatch(x.data(), y.data(), z.data(), which.size(), v.data());
    stats_.evaluations += which.size();
    for (std::size_t w = 0; w < which.size(); ++w) {
      const std::size_t i = which[w];
      const double fv = combine(v[w], g_.boxField(x[w], y[w], z[w]));
      if (fv == 0.0 || std::isnan(fv)) {
        active[i] = 0;
        continue;
      }
      illinoisUpdate(b[i], t[i], fv);
      if (b[i].tb - b[i].ta < kRootBracket) active[i] = 0;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Root& r = roots_[i];
    const double u = std::clamp(t[i], kEdgeMargin, 1.0 - kEdgeMargin);
    Vec3f p;
    for (int k = 0; k < 3; ++k) p[k] = fineF(k, r.f[k]);
    const double a0 = fineCoord(r.d, r.f[r.d]), a1 = fineCoord(r.d, r.f[r.d] + 1);
    p[r.d] = static_cast<float>(a0 + u * (a1 - a0));
    if (!(p[r.d] > fineF(r.d, r.f[r.d]) && p[r.d] < fineF(r.d, r.f[r.d] + 1)))
      throw Abort("a half cell is too small for float32");
    mesh_.positions[r.v] = p;
  }
}

}  // namespace refinement
}  // namespace frep

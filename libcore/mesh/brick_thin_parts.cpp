// A brick's parts thinner than a cell (mesh/hidden_parts.h): the grid edges a thin part
// crosses between two points of the other side, found and proved.
#include "mesh/brick_mesher.h"

namespace frep {
namespace meshing {

std::size_t BrickMesher::findThinParts(const Field& field, const Field& whole, const CellRange& r,
                                       const std::int64_t n[3], Scratch& s,
                                       BrickResult& out) const {
  out.thinSolid = out.thinGaps = out.tips = 0;
  out.hiddenEdges.clear();
  out.tipEdges.clear();
  out.exampleUnseen = false;
  out.exampleKey = std::numeric_limits<std::uint64_t>::max();
  siftTents(r, n, s);
  if (s.tentEdge.empty()) return 0;
  std::size_t evaluations = s.lx.size();
  if (!s.lx.empty()) {  // the points beside the candidates that the brick does not hold
    s.lf.resize(s.lx.size());
    whole.evalBatch(s.lx.data(), s.ly.data(), s.lz.data(), s.lx.size(), s.lf.data());
    for (std::size_t i = 0; i < s.lx.size(); ++i) {
      const double v = combine(s.lf[i], g_.boxField(s.lx[i], s.ly[i], s.lz[i]));
      (s.lazyOf[i] % 2 ? s.tentAfter : s.tentBefore)[s.lazyOf[i] / 2] = v;
    }
  }
  // the tents, and the points where their lines meet, evaluated in one batch
  const std::int64_t stride[3] = {1, n[0], n[0] * n[1]};
  const double* f = s.f.data();
  for (auto* v : {&s.lx, &s.ly, &s.lz}) v->clear();
  s.lazyOf.clear();
  for (std::size_t c = 0; c < s.tentEdge.size(); ++c) {
    const std::uint32_t id = s.tentEdge[c] / 3;
    const int a = static_cast<int>(s.tentEdge[c] % 3);
    double t;
    if (!tentCrossesZero(s.tentBefore[c], f[id], f[id + stride[a]], s.tentAfter[c], &t)) continue;
    const std::int64_t l[3] = {id % n[0], (id / n[0]) % n[1], id / (n[0] * n[1])};
    Vec3 p;
    for (int b = 0; b < 3; ++b) p[b] = g_.coord(b, r.lo[b] + l[b]);
    p[a] += t * (g_.coord(a, r.lo[a] + l[a] + 1) - p[a]);
    s.lx.push_back(p[0]);
    s.ly.push_back(p[1]);
    s.lz.push_back(p[2]);
    s.lazyOf.push_back(static_cast<std::uint32_t>(c));
  }
  if (s.lx.empty()) return evaluations;
  evaluations += s.lx.size();
  s.lf.resize(s.lx.size());
  field.evalBatch(s.lx.data(), s.ly.data(), s.lz.data(), s.lx.size(), s.lf.data());
  for (std::size_t i = 0; i < s.lx.size(); ++i) {
    const std::uint32_t edge = s.tentEdge[s.lazyOf[i]], id = edge / 3;
    const int a = static_cast<int>(edge % 3);
    const bool inside = isInside(f[id]);
    if (isInside(combine(s.lf[i], g_.boxField(s.lx[i], s.ly[i], s.lz[i]))) == inside) continue;
    const std::int64_t l[3] = {id % n[0], (id / n[0]) % n[1], id / (n[0] * n[1])};
    bool mine = true;  // (the edge's owner: as for its vertex, the brick of its lower point)
    for (int b = 0; b < 3; ++b)
      mine = mine && (r.lo[b] + l[b] < r.hi[b] || r.hi[b] == g_.points[b] - 1);
    if (!mine) continue;
    const bool unseen = seenNowhereNear(whole, r, n, l, a, inside, s, &evaluations);
    if (unseen)
      ++(inside ? out.thinGaps : out.thinSolid);
    else
      ++out.tips;
    const std::uint64_t key = g_.linear(r.lo[0] + l[0], r.lo[1] + l[1], r.lo[2] + l[2]) * 3 +
                              static_cast<std::uint64_t>(a);
    if (opt_.settings.refining()) (unseen ? out.hiddenEdges : out.tipEdges).push_back(key);
    // the example: of a part seen nowhere near where there is one
    if (unseen > out.exampleUnseen || (unseen == out.exampleUnseen && key < out.exampleKey)) {
      out.exampleUnseen = unseen;
      out.exampleKey = key;
      out.example = {s.lx[i], s.ly[i], s.lz[i]};
    }
  }
  return evaluations;
}

void BrickMesher::siftTents(const CellRange& r, const std::int64_t n[3], Scratch& s) const {
  s.tentEdge.clear();
  s.tentBefore.clear();
  s.tentAfter.clear();
  for (auto* v : {&s.lx, &s.ly, &s.lz}) v->clear();
  s.lazyOf.clear();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::int64_t stride[3] = {1, n[0], n[0] * n[1]};
  const double* f = s.f.data();
  const char* need = s.need.data();
  auto queue = [&](const std::int64_t l[3], int a, std::int64_t step, std::uint32_t slot) {
    std::int64_t q[3] = {r.lo[0] + l[0], r.lo[1] + l[1], r.lo[2] + l[2]};
    q[a] += step;
    s.lx.push_back(g_.coord(0, q[0]));
    s.ly.push_back(g_.coord(1, q[1]));
    s.lz.push_back(g_.coord(2, q[2]));
    s.lazyOf.push_back(slot);
  };
  auto consider = [&](const std::int64_t l[3], int a) {
    const std::int64_t d = stride[a];
    const std::int64_t id = l[0] + n[0] * (l[1] + n[1] * l[2]);
    const std::int64_t globalLow = r.lo[a] + l[a];
    if (globalLow < 1 || globalLow + 2 >= g_.points[a]) return;  // the outer layer
    const bool heldBefore = l[a] >= 1 && need[id - d];
    const bool heldAfter = l[a] + 2 < n[a] && need[id + 2 * d];
    const double before = heldBefore ? f[id - d] : nan, after = heldAfter ? f[id + 2 * d] : nan;
    if (heldBefore && !heldAfter && !sideCrossesZero(f[id], before)) return;
    if (heldAfter && !heldBefore && !sideCrossesZero(f[id + d], after)) return;
    const std::uint32_t c = static_cast<std::uint32_t>(s.tentEdge.size());
    s.tentEdge.push_back(static_cast<std::uint32_t>(id) * 3 + static_cast<std::uint32_t>(a));
    s.tentBefore.push_back(before);
    s.tentAfter.push_back(after);
    if (!heldBefore) queue(l, a, -1, c * 2);
    if (!heldAfter) queue(l, a, 2, c * 2 + 1);
  };
  std::vector<double>& flags = s.tentFlags;
  std::vector<double>& passBefore = s.tentPassBefore;
  std::vector<double>& passAfter = s.tentPassAfter;
  flags.resize(static_cast<std::size_t>(n[0]));
  passBefore.resize(static_cast<std::size_t>(n[0]));
  passAfter.resize(static_cast<std::size_t>(n[0]));
  // per row along x: whether it holds an evaluated point (an edge needs two; the rows of a
  // proven sub-block hold none)
  std::vector<std::uint8_t>& rowEvaluated = s.rowEvaluated;
  rowEvaluated.resize(static_cast<std::size_t>(n[1] * n[2]));
  for (std::int64_t q = 0; q < n[1] * n[2]; ++q)
    rowEvaluated[q] = std::memchr(need + q * n[0], 1, static_cast<std::size_t>(n[0])) != nullptr;
  for (int a = 0; a < 3; ++a) {
    const std::int64_t d = stride[a];
    std::int64_t l[3] = {0, 0, 0};
    for (l[2] = 0; l[2] < n[2]; ++l[2])
      for (l[1] = 0; l[1] < n[1]; ++l[1]) {
        if (a > 0 && l[a] + 1 >= n[a]) continue;  // no edge along a from this row
        const std::int64_t rowIndex = l[1] + n[1] * l[2], row = n[0] * rowIndex;
        const double* here = f + row;
        if (!rowEvaluated[rowIndex]) continue;
        if (a == 0) {
          // along the row: its inner edges in bulk, the first and last one by one
          if (sieveTentRow(here, here + 1, here + 2, here + 3, n[0] - 3, flags.data()))
            for (std::int64_t i = 0; i + 3 < n[0]; ++i)
              if (flags[i] != 0.0) {
                l[0] = i + 1;
                consider(l, a);
              }
          for (std::int64_t i : {std::int64_t(0), n[0] - 2}) {
            l[0] = i;
            if (need[row + i] && need[row + i + 1] && isInside(here[i]) == isInside(here[i + 1]))
              consider(l, a);
          }
          continue;
        }
        if (!rowEvaluated[rowIndex + (a == 1 ? 1 : n[1])]) continue;
        // across rows: a neighbour layer beyond the brick's face is not held; a value of
        // the ends' side at infinity lets the sieve pass it, to be queued if need be
        const double* before = here - d;
        const double* after = here + 2 * d;
        if (l[a] < 1) {
          for (std::int64_t i = 0; i < n[0]; ++i) passBefore[i] = here[i] < 0.0 ? -inf : inf;
          before = passBefore.data();
        }
        if (l[a] + 2 >= n[a]) {
          for (std::int64_t i = 0; i < n[0]; ++i) passAfter[i] = here[i + d] < 0.0 ? -inf : inf;
          after = passAfter.data();
        }
        if (!sieveTentRow(before, here, here + d, after, n[0], flags.data())) continue;
        for (std::int64_t i = 0; i < n[0]; ++i)
          if (flags[i] != 0.0) {
            l[0] = i;
            consider(l, a);
          }
      }
  }
}

bool BrickMesher::seenNowhereNear(const Field& whole, const CellRange& r, const std::int64_t n[3],
                                  const std::int64_t l[3], int a, bool inside, const Scratch& s,
                                  std::size_t* evaluations) const {
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  for (int k = 0; k < 18; ++k) {
    std::int64_t q[3] = {l[0], l[1], l[2]};
    q[a] += k % 2;
    q[b] += (k / 2) % 3 - 1;
    q[c] += k / 6 - 1;
    bool held = true;
    for (int e = 0; e < 3; ++e) held = held && q[e] >= 0 && q[e] < n[e];
    double v;
    if (held) {
      v = s.f[static_cast<std::size_t>(q[0] + n[0] * (q[1] + n[1] * q[2]))];
    } else {
      std::int64_t gq[3];
      for (int e = 0; e < 3; ++e) gq[e] = r.lo[e] + q[e];
      if (gq[b] < 0 || gq[c] < 0 || gq[b] >= g_.points[b] || gq[c] >= g_.points[c]) continue;
      const double x = g_.coord(0, gq[0]), y = g_.coord(1, gq[1]), z = g_.coord(2, gq[2]);
      v = combine(whole.eval(x, y, z), g_.boxField(x, y, z));
      ++*evaluations;
    }
    if (isInside(v) != inside) return false;
  }
  return true;
}

}  // namespace meshing
}  // namespace frep

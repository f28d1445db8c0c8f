// The refiner's seam: the open edges the region's removal leaves, as lines on the region's
// faces, cut where they cross the faces' midlines.
#include "mesh/refiner.h"

namespace frep {
namespace refinement {

void Refiner::findEdgeVertices() {
  const auto& P = mesh_.positions;
  edgeVertex_.clear();
  std::vector<std::uint8_t> seen(P.size(), 0);
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    if (!removed_[t]) continue;
    for (std::uint32_t v : mesh_.triangles[t]) {
      if (seen[v]) continue;
      seen[v] = 1;
      int on = 0, along = -1;
      std::int64_t l[3];
      for (int a = 0; a < 3; ++a) {
        l[a] = planeAt(a, P[v][a]);
        if (l[a] >= 0)
          ++on;
        else
          along = a;
      }
      if (on != 2) continue;
      l[along] = cellAt(along, P[v][along]);
      if (l[along] < 0) continue;
      edgeVertex_[g_.linear(l[0], l[1], l[2]) * 3 + static_cast<std::uint64_t>(along)] = v;
    }
  }
}

void Refiner::findSeam() {
  const auto& P = mesh_.positions;
  const std::size_t T = mesh_.triangles.size(), V = P.size();
  std::vector<std::uint8_t> touched(V, 0);
  std::unordered_set<std::uint64_t> removedEdges;
  for (std::size_t t = 0; t < T; ++t) {
    if (!removed_[t]) continue;
    const Triangle& tr = mesh_.triangles[t];
    for (int e = 0; e < 3; ++e) {
      touched[tr[e]] = 1;
      removedEdges.insert(dirKey(tr[e], tr[(e + 1) % 3]));
    }
    ++stats_.trianglesRemoved;
  }
  std::size_t open = 0;  // removed edges whose partner stays
  for (std::uint64_t k : removedEdges)
    if (!removedEdges.count((k << 32) | (k >> 32))) ++open;
  std::size_t seamEdges = 0;
  for (std::size_t t = 0; t < T; ++t) {
    if (removed_[t]) continue;
    const Triangle& tr = mesh_.triangles[t];
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t p = tr[e], q = tr[(e + 1) % 3];
      if (!touched[p] || !touched[q] || !removedEdges.count(dirKey(q, p))) continue;
      ++seamEdges;
      addSeamLine(p, q);
    }
  }
  throwFailures();
  if (seamEdges != open) throw Abort("the removed triangles do not close up with the rest");
}

void Refiner::addSeamLine(std::uint32_t p, std::uint32_t q) {
  try {
    addSeamLineOrFail(p, q);
  } catch (const Abort&) {
    // the cubes round both ends join, so the seam moves away from the line
    for (const Vec3f& x : {mesh_.positions[p], mesh_.positions[q]}) {
      std::int64_t lo[3], hi[3];
      for (int a = 0; a < 3; ++a) span(a, x[a], x[a], &lo[a], &hi[a]);
      for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
          for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
            (region_.count(cubeId(i, j, k)) ? failed_.fallback : failed_.extra)
                .push_back(cubeId(i, j, k));
    }
  }
}

void Refiner::addSeamLineOrFail(std::uint32_t p, std::uint32_t q) {
  const auto& P = mesh_.positions;
  int axis = -1;
  std::int64_t plane = -1;
  for (int a = 0; a < 3; ++a) {
    if (P[p][a] != P[q][a]) continue;
    const std::int64_t j = planeAt(a, P[p][a]);
    if (j < 0) continue;
    if (axis >= 0) throw Abort("a seam line runs along a grid line");
    axis = a;
    plane = j;
  }
  if (axis < 0) throw Abort("a seam line lies on no face of the grid");
  std::int64_t cell[3];
  cell[axis] = plane;
  for (int b = 0; b < 3; ++b) {
    if (b == axis) continue;
    cell[b] = cellAt(b, 0.5 * (double(P[p][b]) + double(P[q][b])));
    if (cell[b] < 0) throw Abort("a seam line's midpoint lies on a grid line");
  }
  std::int64_t below[3] = {cell[0], cell[1], cell[2]};
  below[axis] -= 1;
  if (inOmega(below) == inOmega(cell))
    throw Abort("a seam line lies on a face inside or outside the region");
  const std::uint64_t key =
      g_.linear(cell[0], cell[1], cell[2]) * 3 + static_cast<std::uint64_t>(axis);
  SeamFace& f = seam_[key];
  f.axis = axis;
  for (int a = 0; a < 3; ++a) f.cell[a] = cell[a];
  f.lines.push_back({p, q});
}

void Refiner::cutSeamFace(SeamFace& f) {
  const int a = f.axis, b = (a + 1) % 3, c = (a + 2) % 3;
  float midF[3] = {0.f, 0.f, 0.f};
  midF[b] = static_cast<float>(g_.mid(b, f.cell[b]));
  midF[c] = static_cast<float>(g_.mid(c, f.cell[c]));
  FaceCut cut;
  cells_.cutFace(a, f.lines, midF, &cut);
  for (int q = 0; q < 4; ++q) {
    f.halfMid[q] = std::move(cut.halfMid[q]);
    for (const Seg& piece : cut.quarter[q]) f.quarter[q].push_back({piece.to, piece.from});
  }
  // the centre's side from each half midline: its outer end's side, flipped at each cut
  int centre = -1;
  for (int half = 0; half < 4; ++half) {
    std::int64_t e[3];  // the fine point at the half midline's outer end
    for (int k = 0; k < 3; ++k) e[k] = 2 * f.cell[k];
    const int along = half < 2 ? c : b, across = half < 2 ? b : c;
    e[across] += 1;
    e[along] += (half % 2) ? 2 : 0;
    const bool end = virtualSign(e);
    const int s = (end ? 1 : 0) ^ static_cast<int>(f.halfMid[half].size() % 2);
    if (centre >= 0 && s != centre) throw Abort("a seam face's centre has no one side");
    centre = s;
  }
  f.centreInside = centre == 1;
  f.cut = true;
}

}  // namespace refinement
}  // namespace frep

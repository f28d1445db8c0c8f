// A brick's crossed cubes as loops and fans (mesh/cube_loops.h): ambiguous faces decided by
// the field, the face diagonals kept, each loop capped.
#include "mesh/brick_mesher.h"

namespace frep {
namespace meshing {

void BrickMesher::resolveAmbiguousFaces(const Field& field, const CellRange& r,
                                        const std::int64_t c[3], Scratch& s) const {
  const CubeLoopTables& cl = cubeLoopTables();
  auto evaluate = [&] {
    s.af.resize(s.ax.size());
    field.evalBatch(s.ax.data(), s.ay.data(), s.az.data(), s.ax.size(), s.af.data());
    for (std::size_t i = 0; i < s.ax.size(); ++i)
      s.af[i] = combine(s.af[i], g_.boxField(s.ax[i], s.ay[i], s.az[i]));
  };
  auto lowest = [&](std::uint32_t q, std::int64_t g[3]) {
    g[0] = r.lo[0] + q % c[0];
    g[1] = r.lo[1] + (q / c[0]) % c[1];
    g[2] = r.lo[2] + q / (c[0] * c[1]);
  };
  for (auto* v : {&s.ax, &s.ay, &s.az}) v->clear();
  s.centreOf.clear();
  const std::uint32_t cubes = static_cast<std::uint32_t>(c[0] * c[1] * c[2]);
  for (std::uint32_t q = 0; q < cubes; ++q) {
    const int ambiguous = cl.ambiguous[s.cellMask[q]];
    if (!ambiguous) continue;
    std::int64_t g[3];
    lowest(q, g);
    for (int f = 0; f < 6; ++f) {
      if (!((ambiguous >> f) & 1)) continue;
      const Vec3 p = faceCentre(g, f);
      s.ax.push_back(p[0]);
      s.ay.push_back(p[1]);
      s.az.push_back(p[2]);
      s.centreOf.push_back(q * 6 + static_cast<std::uint32_t>(f));
    }
  }
  if (s.ax.empty()) return;
  evaluate();
  for (std::size_t i = 0; i < s.ax.size(); ++i) {
    const std::uint32_t q = s.centreOf[i] / 6;
    const int f = static_cast<int>(s.centreOf[i] % 6);
    if (flipped(s.cellMask[q], f, s.af[i])) s.cellFlips[q] |= static_cast<std::uint8_t>(1u << f);
  }
  for (auto* v : {&s.ax, &s.ay, &s.az}) v->clear();
  s.centreOf.clear();
  for (std::uint32_t q = 0; q < cubes; ++q) {
    if (!s.cellFlips[q] || cl.fanned(s.cellMask[q], s.cellFlips[q])) continue;
    std::int64_t g[3];
    lowest(q, g);
    s.ax.push_back(g_.mid(0, g[0]));
    s.ay.push_back(g_.mid(1, g[1]));
    s.az.push_back(g_.mid(2, g[2]));
    s.centreOf.push_back(q);
  }
  if (s.ax.empty()) return;
  evaluate();
  s.centreValue.resize(cubes);
  for (std::size_t i = 0; i < s.ax.size(); ++i) s.centreValue[s.centreOf[i]] = s.af[i];
}

void BrickMesher::markKeptDiagonals(const Field& whole, const CellRange& r, const std::int64_t n[3],
                                    const std::int64_t c[3], const std::uint32_t cornerOffset[8],
                                    Scratch& s) const {
  const CubeLoopTables& cl = cubeLoopTables();
  s.kept.assign(static_cast<std::size_t>(n[0] * n[1] * n[2]) * 7, 0);
  s.hx.clear();
  s.hy.clear();
  s.hz.clear();
  s.haloKey.clear();
  s.haloMask.clear();
  s.haloCube.clear();
  for (std::int64_t k = 0, q = 0; k < c[2]; ++k)
    for (std::int64_t j = 0; j < c[1]; ++j)
      for (std::int64_t i = 0; i < c[0]; ++i, ++q) {
        const int mask = s.cellMask[q];
        if (mask == 0 || mask == 255) continue;
        const std::uint32_t base = static_cast<std::uint32_t>(i + n[0] * (j + n[1] * k));
        const bool byTetrahedra = !cl.fanned(mask, s.cellFlips[q]);
        const std::int64_t at[3] = {i, j, k};
        for (int id = kFirstFaceDiagonal; id < kMainDiagonal; ++id) {
          const TetEdge& e = cl.edges[id];
          if (((mask >> e.low) & 1) == ((mask >> (e.low | e.dir)) & 1)) continue;
          const std::uint32_t key = edgeKey(base, cornerOffset, e);
          if (byTetrahedra) {
            s.kept[key] = 1;
            continue;
          }
          const int a = (~e.dir & 1) ? 0 : (~e.dir & 2) ? 1 : 2;  // the face's normal axis
          const int side = (e.low >> a) & 1;
          if (side ? at[a] != c[a] - 1 : at[a] != 0) continue;  // inside the brick
          const std::int64_t far = r.lo[a] + at[a] + (side ? 2 : -1);
          if (far < 0 || far >= g_.points[a]) continue;  // the grid's edge: never crossed
          std::uint8_t known = 0;  // the neighbour's corners on the shared face, from here
          for (int v = 0; v < 8; ++v)
            if (((v >> a) & 1) != side && ((mask >> (v ^ (1 << a))) & 1)) known |= 1u << v;
          s.haloKey.push_back(key);
          s.haloMask.push_back(known);
          s.haloMask.push_back(static_cast<std::uint8_t>(a * 2 + side));
          for (int b = 0; b < 3; ++b)
            s.haloCube.push_back(r.lo[b] + at[b] + (b == a ? (side ? 1 : -1) : 0));
          for (int v = 0; v < 8; ++v) {
            if (((v >> a) & 1) != side) continue;
            std::int64_t p[3];
            for (int b = 0; b < 3; ++b) p[b] = r.lo[b] + at[b] + ((v >> b) & 1);
            p[a] = far;
            s.hx.push_back(g_.coord(0, p[0]));
            s.hy.push_back(g_.coord(1, p[1]));
            s.hz.push_back(g_.coord(2, p[2]));
          }
        }
      }
  if (s.haloKey.empty()) return;
  s.hf.resize(s.hx.size());
  whole.evalBatch(s.hx.data(), s.hy.data(), s.hz.data(), s.hx.size(), s.hf.data());
  for (std::size_t h = 0; h < s.haloKey.size(); ++h) {
    int mask = s.haloMask[2 * h];
    const int a = s.haloMask[2 * h + 1] / 2, side = s.haloMask[2 * h + 1] % 2;
    for (int v = 0, f = 0; v < 8; ++v) {
      if (((v >> a) & 1) != side) continue;
      const std::size_t at = 4 * h + static_cast<std::size_t>(f++);
      if (isInside(combine(s.hf[at], g_.boxField(s.hx[at], s.hy[at], s.hz[at])))) mask |= 1 << v;
    }
    // the neighbour's own ambiguous faces are split as it splits them (whole field)
    int flips = 0;
    for (int f = 0; f < 6; ++f) {
      if (!((cl.ambiguous[mask] >> f) & 1)) continue;
      const Vec3 p = faceCentre(&s.haloCube[3 * h], f);
      const double v = combine(whole.eval(p[0], p[1], p[2]), g_.boxField(p[0], p[1], p[2]));
      if (flipped(mask, f, v)) flips |= 1 << f;
    }
    if (!cl.fanned(mask, flips)) s.kept[s.haloKey[h]] = 1;
  }
}

void BrickMesher::capLoops(const Field& whole, const CellRange& r, const std::int64_t n[3],
                           bool sharp, Scratch& s, BrickResult& out) const {
  const CubeLoopTables& cl = cubeLoopTables();
  const std::vector<Vec3f>& P = out.positions;
  const bool flat = opt_.settings.dropFlatVertices;
  if (flat) {  // (by a cube's lowest grid point, as the loops name their cubes)
    s.fanFirst.assign(static_cast<std::size_t>(n[0] * n[1] * n[2]), 0);
    s.fanCount.assign(s.fanFirst.size(), 0);
  }
  // Flat vertices (removeFlatVertices) are sought only where the cubes have plain fans.
  auto recordFan = [&](std::uint32_t base, std::size_t first) {
    if (!flat) return;
    s.fanFirst[base] = static_cast<std::uint32_t>(first);
    s.fanCount[base] = static_cast<std::uint8_t>(out.triangles.size() - first);
  };
  for (std::size_t p = 0; p < s.loops.size();) {
    const std::uint32_t base = s.loops[p], len = s.loops[p + 1] & 255, mask = s.loops[p + 1] >> 8;
    const std::uint32_t* L = &s.loops[p + 2];
    p += 2 + 2 * static_cast<std::size_t>(len);
    // (i < 2 len: wrapped by a comparison, not a division)
    auto v = [&](std::uint32_t i) { return L[2 * (i < len ? i : i - len)]; };
    auto id = [&](std::uint32_t i) { return L[2 * (i < len ? i : i - len) + 1]; };
    if (sharp && placeFeature(whole, r, n, base, mask, L, len, s, out)) continue;
    const std::size_t first = out.triangles.size();
    if (len == 3) {  // (one triangle, whichever the apex)
      out.triangles.push_back({v(0), v(1), v(2)});
      recordFan(base, first);
      continue;
    }
    int best = -1;
    double bestQuality = -1.0;
    // (a quad's apexes a and a + 2 make the same fan: the first two decide)
    for (std::uint32_t a = 0; a < (len == 4 ? 2u : len); ++a) {
      bool sees = true;
      for (std::uint32_t j = 2; j + 1 < len && sees; ++j)
        sees = (cl.faces[id(a + j)] & cl.faces[id(a)]) == 0;
      if (!sees) continue;
      double q = std::numeric_limits<double>::infinity();
      for (std::uint32_t j = 1; j + 1 < len; ++j)
        q = std::min(q, triangleQuality(P[v(a)], P[v(a + j)], P[v(a + j + 1)]));
      if (q > bestQuality) {
        bestQuality = q;
        best = static_cast<int>(a);
      }
    }
    if (best >= 0) {
      const std::uint32_t a = static_cast<std::uint32_t>(best);
      for (std::uint32_t j = 1; j + 1 < len; ++j)
        out.triangles.push_back({v(a), v(a + j), v(a + j + 1)});
      recordFan(base, first);
      continue;
    }
    const std::uint32_t apex = innerVertex(r, n, base, L, len, s, out);
    for (std::uint32_t j = 0; j < len; ++j) out.triangles.push_back({apex, v(j), v(j + 1)});
    recordFan(base, first);
  }
}

}  // namespace meshing
}  // namespace frep

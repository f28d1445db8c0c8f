// The mesher's work on one brick (BrickMesher::run): the field at the grid points, the
// crossed cubes, the vertices on their edges (root finding) and the triangles.
#include "mesh/brick_mesher.h"

namespace frep {
namespace meshing {

std::size_t BrickMesher::run(const Field& field, const Field& whole, const CellRange& r, Scratch& s,
                             BrickResult& out) const {
  const std::int64_t n[3] = {r.hi[0] - r.lo[0] + 1, r.hi[1] - r.lo[1] + 1, r.hi[2] - r.lo[2] + 1};
  const std::size_t count = static_cast<std::size_t>(n[0] * n[1] * n[2]);
  auto local = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return static_cast<std::uint32_t>(i + n[0] * (j + n[1] * k));
  };

  // 1. Field at the grid points of the brick. Sub-blocks of kSubCells^3 cells that
  // intervals prove uniform need no values: none of their cells is crossed, and every
  // crossed edge lies in a cell of an unproven sub-block, whose corners are all evaluated.
  // Their other points get a stand-in of the proven sign, an infinity, read only by the
  // cell masks and the sieve for thin parts (sieveTentRow), so the mesh is the same as with
  // every point evaluated.
  s.f.resize(count);
  s.need.assign(count, 0);
  s.standIn.assign(count, 0);
  const std::int64_t c[3] = {n[0] - 1, n[1] - 1, n[2] - 1};
  for (std::int64_t k0 = 0; k0 < c[2]; k0 += kSubCells)
    for (std::int64_t j0 = 0; j0 < c[1]; j0 += kSubCells)
      for (std::int64_t i0 = 0; i0 < c[0]; i0 += kSubCells) {
        const std::int64_t i1 = std::min(i0 + kSubCells, c[0]), j1 = std::min(j0 + kSubCells, c[1]),
                           k1 = std::min(k0 + kSubCells, c[2]);
        CellRange sub{{r.lo[0] + i0, r.lo[1] + j0, r.lo[2] + k0},
                      {r.lo[0] + i1, r.lo[1] + j1, r.lo[2] + k1}};
        const bool whole = i1 - i0 == c[0] && j1 - j0 == c[1] && k1 - k0 == c[2];
        const int sign = whole ? 0 : provenSign(field, g_, sub);
        for (std::int64_t k = k0; k <= k1; ++k)
          for (std::int64_t j = j0; j <= j1; ++j)
            for (std::int64_t i = i0; i <= i1; ++i) {
              const std::uint32_t id = local(i, j, k);
              if (sign == 0)
                s.need[id] = 1;
              else
                s.standIn[id] = static_cast<std::int8_t>(sign);
            }
      }
  std::vector<double>&qx = s.qx, &qy = s.qy, &qz = s.qz, &qf = s.qf;
  qx.clear();
  qy.clear();
  qz.clear();
  // (a grid point's coordinates are its axes' values: s.x, s.y and s.z hold them per axis)
  std::vector<double>* onAxis[3] = {&s.x, &s.y, &s.z};
  for (int a = 0; a < 3; ++a) {
    onAxis[a]->resize(static_cast<std::size_t>(n[a]));
    for (std::int64_t i = 0; i < n[a]; ++i) (*onAxis[a])[i] = g_.coord(a, r.lo[a] + i);
  }
  const double *cx = s.x.data(), *cy = s.y.data(), *cz = s.z.data();
  for (std::int64_t k = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i)
        if (s.need[local(i, j, k)]) {
          qx.push_back(cx[i]);
          qy.push_back(cy[j]);
          qz.push_back(cz[k]);
        }
  qf.resize(qx.size());
  field.evalBatch(qx.data(), qy.data(), qz.data(), qx.size(), qf.data());
  for (std::int64_t k = 0, id = 0, q = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i, ++id)
        s.f[id] = s.need[id] ? combine(qf[q++], g_.boxField(cx[i], cy[j], cz[k]))
                             : s.standIn[id] * std::numeric_limits<double>::infinity();
  const std::size_t evaluated =
      qx.size() + (opt_.findThinParts ? findThinParts(field, whole, r, n, s, out) : 0);

  // 2. The crossed cubes. With the cube extraction a cube whose surface meets its faces in
  // one loop is capped by a fan over that loop (after the roots are known); any other
  // crossed cube keeps its tetrahedra's polygons, and then the face diagonals it crosses
  // stay on its neighbours' loops too, so both sides of every face draw the same line.
  const KuhnTables& kt = kuhnTables();
  const CubeLoopTables& cl = cubeLoopTables();
  const bool byCubes = opt_.settings.mesher == Extraction::Cubes;
  auto byTetrahedra = [&](int mask, int flips) { return !byCubes || !cl.fanned(mask, flips); };
  s.edgeVertex.assign(count * 7, -1);
  s.polys.clear();
  s.loops.clear();
  std::vector<std::uint32_t>& edgeOf = s.edgeOf;
  edgeOf.clear();
  const std::uint32_t cornerOffset[8] = {0,
                                         local(1, 0, 0),
                                         local(0, 1, 0),
                                         local(1, 1, 0),
                                         local(0, 0, 1),
                                         local(1, 0, 1),
                                         local(0, 1, 1),
                                         local(1, 1, 1)};
  const std::size_t cubes = static_cast<std::size_t>(c[0] * c[1] * c[2]);
  s.cellMask.resize(cubes);
  // (a point's sign and its +x neighbour's as two bits, so a cube's mask is four of them:
  // corners 0-1, 2-3, 4-5 and 6-7 differ by x only)
  s.insidePair.resize(count);
  for (std::size_t id = 0; id + 1 < count; ++id)
    s.insidePair[id] = static_cast<std::uint8_t>(isInside(s.f[id]) | isInside(s.f[id + 1]) << 1);
  for (std::int64_t k = 0, q = 0; k < c[2]; ++k)
    for (std::int64_t j = 0; j < c[1]; ++j)
      for (std::int64_t i = 0; i < c[0]; ++i, ++q) {
        const std::uint8_t* p = &s.insidePair[local(i, j, k)];
        s.cellMask[q] = static_cast<std::uint8_t>(
            p[0] | p[cornerOffset[2]] << 2 | p[cornerOffset[4]] << 4 | p[cornerOffset[6]] << 6);
      }
  s.cellFlips.assign(cubes, 0);
  if (byCubes) {
    resolveAmbiguousFaces(field, r, c, s);
    markKeptDiagonals(whole, r, n, c, cornerOffset, s);
  }
  auto vertexFor = [&](std::uint32_t key) {
    std::int32_t& slot = s.edgeVertex[key];
    if (slot < 0) {
      slot = static_cast<std::int32_t>(edgeOf.size());
      edgeOf.push_back(key);
    }
    return static_cast<std::uint32_t>(slot);
  };
  for (std::int64_t k = 0, q = 0; k < c[2]; ++k)
    for (std::int64_t j = 0; j < c[1]; ++j)
      for (std::int64_t i = 0; i < c[0]; ++i, ++q) {
        const int cellMask = s.cellMask[q];
        if (cellMask == 0 || cellMask == 255) continue;
        const std::uint32_t base = local(i, j, k);
        const int flips = s.cellFlips[q];
        if (!byTetrahedra(cellMask, flips)) {
          // loop entry: cube base, length, then (vertex, cube-local id) pairs
          const CubeLoopCase& lc = cl.caseOf(cellMask, flips);
          const std::size_t head = s.loops.size();
          s.loops.push_back(base);
          s.loops.push_back(static_cast<std::uint32_t>(cellMask) << 8);  // | length
          for (int v = 0; v < lc.length; ++v) {
            const std::uint32_t key = edgeKey(base, cornerOffset, cl.edges[lc.ids[v]]);
            if (lc.ids[v] >= kFirstFaceDiagonal && !s.kept[key]) continue;
            s.loops.push_back(vertexFor(key));
            s.loops.push_back(lc.ids[v]);
            ++s.loops[head + 1];
          }
          continue;
        }
        if (flips != 0) {
          // several loops and a face off Kuhn's split: the twelve tetrahedra round the
          // centre, whose vertices on the centre's edges are this cube's alone
          s.crossings.clear();
          centredCubeCrossings(cellMask, isInside(s.centreValue[q]), flips, s.crossings);
          std::int32_t onCentreEdge[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
          for (const TetCrossing& x : s.crossings) {
            std::uint32_t ids[4] = {0, 0, 0, UINT32_MAX};
            for (int e = 0; e < x.count; ++e) {
              const int u = x.from[e], w = x.to[e];
              if (u == kCubeCentre || w == kCubeCentre) {
                const int corner = u == kCubeCentre ? w : u;
                if (onCentreEdge[corner] < 0) {
                  onCentreEdge[corner] = static_cast<std::int32_t>(edgeOf.size());
                  edgeOf.push_back(static_cast<std::uint32_t>(count * 7 + q * 8 + corner));
                }
                ids[e] = static_cast<std::uint32_t>(onCentreEdge[corner]);
              } else {
                ids[e] = vertexFor(edgeKey(base, cornerOffset, edgeBetween(u, w)));
              }
            }
            s.polys.insert(s.polys.end(), ids, ids + 4);
          }
          continue;
        }
        for (int t = 0; t < 6; ++t) {
          const auto& tet = kt.tets[t];
          int mask = 0;
          for (int v = 0; v < 4; ++v) mask |= ((cellMask >> tet[v]) & 1) << v;
          const TetPolygon& poly = kt.polygons[t][mask];
          if (poly.count == 0) continue;
          std::uint32_t ids[4] = {0, 0, 0, UINT32_MAX};
          for (int e = 0; e < poly.count; ++e)
            ids[e] = vertexFor(edgeKey(base, cornerOffset, poly.edges[e]));
          s.polys.insert(s.polys.end(), ids, ids + 4);
        }
      }

  // 3. Vertices: root of the field along each crossed edge.
  out.keys.resize(edgeOf.size());
  out.positions.resize(edgeOf.size());
  const std::size_t rootEvaluations = locateRoots(field, s, edgeOf, n, r, out);
  const std::size_t m = edgeOf.size();
  // Ownership: an edge belongs to the brick whose half-open cell range holds its lower grid
  // point (the last brick on an axis also holds the grid's last points).
  out.owner.resize(m);
  for (std::size_t e = 0; e < m; ++e) {
    if (edgeOf[e] >= count * 7) {  // on a centre's edge: inside one cube of this brick
      out.owner[e] = Ownership::Own;
      continue;
    }
    const std::uint32_t low = edgeOf[e] / 7;
    const std::int64_t l[3] = {low % n[0], (low / n[0]) % n[1], low / (n[0] * n[1])};
    bool mine = true, lowerFace = false;
    for (int a = 0; a < 3; ++a) {
      mine = mine && (r.lo[a] + l[a] < r.hi[a] || r.hi[a] == g_.points[a] - 1);
      lowerFace = lowerFace || l[a] == 0;
    }
    out.owner[e] = !mine ? Ownership::Other : lowerFace ? Ownership::OwnShared : Ownership::Own;
  }
  // Unit normals from the gradient, with the brick's own (specialised) field, in one batch:
  // of every vertex where sharp features place cube vertices from them, else of the vertices
  // this brick owns (a vertex another brick owns takes that brick's normal in the weld).
  const bool sharp = byCubes && opt_.settings.sharpFeatures;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  s.unit.clear();
  if (sharp || opt_.normals) {
    std::vector<std::uint32_t>& owned = s.owned;
    owned.clear();
    for (std::size_t e = 0; e < m; ++e)
      if (sharp || out.owner[e] != Ownership::Other) owned.push_back(static_cast<std::uint32_t>(e));
    const std::size_t k = owned.size();
    s.gx.resize(k);
    s.gy.resize(k);
    s.gz.resize(k);
    s.grad.resize(k);
    for (std::size_t i = 0; i < k; ++i) {
      const Vec3f& p = out.positions[owned[i]];
      s.gx[i] = Dual(p[0], 1, 0, 0);
      s.gy[i] = Dual(p[1], 0, 1, 0);
      s.gz[i] = Dual(p[2], 0, 0, 1);
    }
    field.evalGradientBatch(s.gx.data(), s.gy.data(), s.gz.data(), k, s.grad.data());
    s.unit.assign(m, Vec3f{nan, nan, nan});
    for (std::size_t i = 0; i < k; ++i)
      s.unit[owned[i]] = vertexNormal(s.grad[i], g_, out.positions[owned[i]]);
  }
  out.triangles.clear();
  out.flippable.clear();
  out.triangles.reserve(s.polys.size() / 2 + s.loops.size() / 2);
  capLoops(whole, r, n, sharp, s, out);  // adds the cubes' inner vertices, owned here
  out.normals.clear();
  if (opt_.normals) {
    out.normals.assign(s.unit.begin(), s.unit.end());
    for (std::size_t e = 0; e < m; ++e)
      if (out.owner[e] == Ownership::Other) out.normals[e] = Vec3f{nan, nan, nan};
  }

  // 4. The tetrahedra's triangles; a quad is split along the diagonal giving the
  // better-shaped pair.
  for (std::size_t p = 0; p < s.polys.size(); p += 4) {
    const std::uint32_t* q = &s.polys[p];
    if (q[3] == UINT32_MAX) {
      out.triangles.push_back({q[0], q[1], q[2]});
      continue;
    }
    const auto& P = out.positions;
    const double splitA = std::min(triangleQuality(P[q[0]], P[q[1]], P[q[2]]),
                                   triangleQuality(P[q[0]], P[q[2]], P[q[3]]));
    const double splitB = std::min(triangleQuality(P[q[0]], P[q[1]], P[q[3]]),
                                   triangleQuality(P[q[1]], P[q[2]], P[q[3]]));
    if (splitA >= splitB) {
      out.triangles.push_back({q[0], q[1], q[2]});
      out.triangles.push_back({q[0], q[2], q[3]});
    } else {
      out.triangles.push_back({q[0], q[1], q[3]});
      out.triangles.push_back({q[1], q[2], q[3]});
    }
  }
  if (byCubes && opt_.settings.dropFlatVertices) removeFlatVertices(r, n, s, out);
  // Every brick's result is held until the weld: no growth slack kept (the triangles'
  // reserve above is a bound, about twice what a brick makes).
  out.keys.shrink_to_fit();
  out.owner.shrink_to_fit();
  out.positions.shrink_to_fit();
  out.normals.shrink_to_fit();
  out.triangles.shrink_to_fit();
  out.flippable.shrink_to_fit();
  return evaluated + rootEvaluations;
}

std::size_t BrickMesher::locateRoots(const Field& field, Scratch& s,
                                     const std::vector<std::uint32_t>& edgeOf,
                                     const std::int64_t n[3], const CellRange& r,
                                     BrickResult& out) const {
  const std::size_t m = edgeOf.size();
  for (auto* v : {&s.px, &s.py, &s.pz, &s.dx, &s.dy, &s.dz, &s.ta, &s.tb, &s.fa, &s.fb})
    v->resize(m);
  s.lastSide.assign(m, 0);
  const std::uint64_t edgeKeys = static_cast<std::uint64_t>(n[0] * n[1] * n[2]) * 7;
  const std::int64_t c[3] = {n[0] - 1, n[1] - 1, n[2] - 1};
  for (std::size_t e = 0; e < m; ++e) {
    const std::uint32_t key = edgeOf[e];
    if (key >= edgeKeys) {
      // from the centre of cube q to its corner: keyed after every grid edge of the grid
      const std::uint32_t q = static_cast<std::uint32_t>((key - edgeKeys) / 8),
                          corner = (key - edgeKeys) % 8;
      const std::int64_t l[3] = {q % c[0], (q / c[0]) % c[1], q / (c[0] * c[1])};
      double at[3], to[3];
      for (int a = 0; a < 3; ++a) {
        at[a] = g_.mid(a, r.lo[a] + l[a]);
        to[a] = g_.coord(a, r.lo[a] + l[a] + ((corner >> a) & 1));
      }
      out.keys[e] = g_.centreEdgeKey(r.lo[0] + l[0], r.lo[1] + l[1], r.lo[2] + l[2], corner);
      s.px[e] = at[0];
      s.py[e] = at[1];
      s.pz[e] = at[2];
      s.dx[e] = to[0] - at[0];
      s.dy[e] = to[1] - at[1];
      s.dz[e] = to[2] - at[2];
      s.ta[e] = 0.0;
      s.tb[e] = 1.0;
      s.fa[e] = s.centreValue[q];
      s.fb[e] = s.f[static_cast<std::uint32_t>(
          (l[0] + (corner & 1)) +
          n[0] * ((l[1] + ((corner >> 1) & 1)) + n[1] * (l[2] + ((corner >> 2) & 1))))];
      continue;
    }
    const std::uint32_t low = key / 7, dir = key % 7 + 1;
    const std::int64_t li = low % n[0], lj = (low / n[0]) % n[1], lk = low / (n[0] * n[1]);
    const std::int64_t gi = r.lo[0] + li, gj = r.lo[1] + lj, gk = r.lo[2] + lk;
    const std::int64_t hi = gi + (dir & 1), hj = gj + ((dir >> 1) & 1), hk = gk + ((dir >> 2) & 1);
    out.keys[e] = g_.linear(gi, gj, gk) * 7 + (dir - 1);
    s.px[e] = g_.coord(0, gi);
    s.py[e] = g_.coord(1, gj);
    s.pz[e] = g_.coord(2, gk);
    s.dx[e] = g_.coord(0, hi) - s.px[e];
    s.dy[e] = g_.coord(1, hj) - s.py[e];
    s.dz[e] = g_.coord(2, hk) - s.pz[e];
    const std::uint32_t highLocal = static_cast<std::uint32_t>(
        (li + (dir & 1)) + n[0] * ((lj + ((dir >> 1) & 1)) + n[1] * (lk + ((dir >> 2) & 1))));
    s.ta[e] = 0.0;
    s.tb[e] = 1.0;
    s.fa[e] = s.f[low];
    s.fb[e] = s.f[highLocal];
  }
  std::vector<double>& t = s.x;  // reuse the grid buffers: the grid values are consumed
  std::vector<double>& ft = s.y;
  std::vector<double> qx(m), qy(m), qz(m);
  t.resize(m);
  ft.resize(m);
  auto interpolate = [&](std::size_t e) {
    return illinoisEstimate(s.ta[e], s.tb[e], s.fa[e], s.fb[e]);
  };
  // An edge leaves the iteration once its bracket is narrower than kRootBracket of the edge,
  // or the next estimate (the one the vertex gets) moves less than kRootStep or gives the
  // same float32 vertex; each edge's steps depend on its own values only, so an edge two
  // bricks share still ends the same in both.
  std::vector<std::uint32_t>& active = s.active;
  active.resize(m);
  for (std::size_t e = 0; e < m; ++e) active[e] = static_cast<std::uint32_t>(e);
  std::size_t evaluations = 0;
  for (int it = 0; it < opt_.rootIterations && !active.empty(); ++it) {
    const std::size_t na = active.size();
    for (std::size_t q = 0; q < na; ++q) {
      const std::uint32_t e = active[q];
      t[e] = interpolate(e);
      qx[q] = s.px[e] + t[e] * s.dx[e];
      qy[q] = s.py[e] + t[e] * s.dy[e];
      qz[q] = s.pz[e] + t[e] * s.dz[e];
    }
    field.evalBatch(qx.data(), qy.data(), qz.data(), na, ft.data());
    evaluations += na;
    std::size_t kept = 0;
    for (std::size_t q = 0; q < na; ++q) {
      const std::uint32_t e = active[q];
      const double v = combine(ft[q], g_.boxField(qx[q], qy[q], qz[q]));
      illinoisUpdate(s.ta[e], s.tb[e], s.fa[e], s.fb[e], s.lastSide[e], t[e], v);
      if (v == 0.0) {  // the root exactly: the final interpolation returns it
        s.ta[e] = s.tb[e] = t[e];
        continue;
      }
      const double tn = interpolate(e);
      const bool settled =
          std::abs(tn - t[e]) < kRootStep || vertexAt(s, e, t[e]) == vertexAt(s, e, tn);
      if (s.tb[e] - s.ta[e] > kRootBracket && !settled) active[kept++] = e;
    }
    active.resize(kept);
  }
  for (std::size_t e = 0; e < m; ++e) {
    out.positions[e] = vertexAt(s, e, std::clamp(interpolate(e), kEdgeMargin, 1.0 - kEdgeMargin));
  }
  return evaluations;
}

}  // namespace meshing
}  // namespace frep

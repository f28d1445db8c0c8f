#include "mesh/refined_cells.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_set>

#include "base/qef.h"
#include "base/triangle_geometry.h"
#include "mesh/crease_flips.h"
#include "mesh/feature_point.h"

namespace frep::refinement {

namespace {

constexpr double kFeatureCos = 0.8;      // as the cube extraction's (mesher.cpp)
constexpr double kFeatureCutoff = 0.02;  // ditto
constexpr double kApexMargin = 0.05;     // of a cell: the fan's apex off its faces
constexpr int kMaxDepth = 2;             // a half cube is split at most this many times more

}  // namespace

// One loop: a fan from a point inside. Several: the cell is split in eight with its faces'
// lines kept (cut where they cross the faces' midlines), down to kMaxDepth.
void CellMesher::meshCell(const Cell& cell, int depth) {
  std::vector<Seg> segs;
  for (const auto& f : cell.face) segs.insert(segs.end(), f.begin(), f.end());
  if (segs.empty()) return;
  std::unordered_map<std::uint32_t, std::uint32_t> next;
  for (const Seg& s : segs)
    if (!next.emplace(s.from, s.to).second) throw Abort("a cell's lines meet at a vertex");
  std::vector<std::uint32_t> loop = {segs[0].from};
  for (std::uint32_t v = segs[0].to; v != segs[0].from;) {
    loop.push_back(v);
    const auto it = next.find(v);
    if (it == next.end()) throw Abort("a cell's lines do not close");
    v = it->second;
    if (loop.size() > segs.size()) throw Abort("a cell's lines do not close");
  }
  if (loop.size() != segs.size()) {
    if (depth >= kMaxDepth) {
      ++stats_.conedCells;
      coneCell(cell);
      return;
    }
    ++stats_.splitCells;
    splitCell(cell, depth);
    return;
  }
  // the apex: where the loop's tangent planes meet (a crease or corner), else the loop's
  // mean, kept inside the cell
  Vec3f apex;
  const bool feature = depth >= 0 && featureApex(cell, loop, &apex);
  if (!feature) {
    double m[3] = {0, 0, 0};
    for (std::uint32_t v : loop)
      for (int a = 0; a < 3; ++a) m[a] += mesh_.positions[v][a];
    for (int a = 0; a < 3; ++a) m[a] /= static_cast<double>(loop.size());
    apex = clampInto(cell, m);
  }
  const std::uint32_t v = newVertex(apex);
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const std::uint32_t a = loop[i], b = loop[(i + 1) % loop.size()];
    // a feature half cube's triangle over the only line on a face may be flipped with its
    // neighbour's (the two half cubes form a box, as two cubes do: mesh/crease_flips.h)
    if (feature && depth == 0) {
      int f = -1;
      for (int k = 0; k < 6 && f < 0; ++k)
        for (const Seg& sg : cell.face[k])
          if (sg.from == a && sg.to == b) f = k;
      if (f >= 0 && cell.face[f].size() == 1)
        flippable_[dirKey(a, b)] = static_cast<std::uint32_t>(added_.size());
    }
    added_.push_back({v, a, b});
  }
}

Vec3f CellMesher::clampInto(const Cell& cell, const double x[3]) const {
  Vec3f p;
  for (int a = 0; a < 3; ++a) {
    const double margin = kApexMargin * (cell.hi[a] - cell.lo[a]);
    p[a] = static_cast<float>(std::clamp(x[a], cell.lo[a] + margin, cell.hi[a] - margin));
    if (!(p[a] > static_cast<float>(cell.lo[a]) && p[a] < static_cast<float>(cell.hi[a])))
      throw Abort("a cell is too small for float32");
  }
  return p;
}

const Vec3f& CellMesher::unitNormal(std::uint32_t v) {
  const auto it = normal_.find(v);
  if (it != normal_.end()) return it->second;
  const Vec3f& p = mesh_.positions[v];
  ++stats_.evaluations;
  return normal_[v] = vertexNormal(field_.evalGradient(p[0], p[1], p[2]), g_, p);
}

// Sharp features as the cube extraction places them (mesher.cpp, placeFeature): where the
// loop's normals spread by over 37 degrees, the point its tangent planes meet (on a crease
// line, moved along it into the cell where it lies outside, or a corner), within a cell of
// the cell and kept inside it; refused where a fan triangle would face against its
// vertices' normals.
bool CellMesher::featureApex(const Cell& cell, const std::vector<std::uint32_t>& loop,
                             Vec3f* apex) {
  double leastCos;
  std::size_t spreadA, spreadB;
  if (!mostDifferentNormals(
          loop.size(), [&](std::size_t i) { return unitNormal(loop[i]); }, &leastCos, &spreadA,
          &spreadB) ||
      leastCos > kFeatureCos)
    return false;
  Quadric q;
  for (std::uint32_t v : loop) {
    const Vec3f& p = mesh_.positions[v];
    const Vec3f& u = unitNormal(v);
    q.addPlane(Vec3{p[0], p[1], p[2]}, Vec3{u[0], u[1], u[2]});
  }
  int rank = 0;
  Vec3 x = q.minimiser(kFeatureCutoff, &rank);
  if (rank < 2) return false;
  if (rank == 2)  // a crease whose nearest point lies outside may still cross the cell
    moveAlongCreaseIntoBox(x, unitNormal(loop[spreadA]), unitNormal(loop[spreadB]), cell.lo,
                           cell.hi);
  for (int a = 0; a < 3; ++a) {
    const double h = cell.hi[a] - cell.lo[a];
    if (!(x[a] > cell.lo[a] - h && x[a] < cell.hi[a] + h)) return false;
  }
  const double xd[3] = {x[0], x[1], x[2]};
  const Vec3f at = clampInto(cell, xd);
  for (std::size_t j = 0; j < loop.size(); ++j) {
    const std::uint32_t u = loop[j], w = loop[(j + 1) % loop.size()];
    const Vec3d nt = triangleCross(at, mesh_.positions[u], mesh_.positions[w]);
    double dot = 0.0;
    for (int a = 0; a < 3; ++a) dot += nt[a] * (double(unitNormal(u)[a]) + unitNormal(w)[a]);
    if (!(dot > 0.0)) return false;
  }
  *apex = at;
  return true;
}

// Crease flips between neighbouring feature half cubes (as the cube extraction's), where
// no split cell cut the line they share.
void CellMesher::flipCreases() {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (const auto& [key, t] : flippable_) {
    const std::uint32_t a = static_cast<std::uint32_t>(key >> 32),
                        b = static_cast<std::uint32_t>(key);
    if (a > b) continue;  // each pair once
    const auto it = flippable_.find(dirKey(b, a));
    if (it == flippable_.end() || cuts_.count(undirected(a, b))) continue;
    pairs.push_back({t, it->second});
  }
  std::sort(pairs.begin(), pairs.end());
  for (const auto& [t1, t2] : pairs) {
    Triangle f1, f2;
    if (flipCrease(added_[t1], added_[t2], mesh_.positions, &f1, &f2)) {
      added_[t1] = f1;
      added_[t2] = f2;
      ++stats_.flips;
    }
  }
}

// ---- several loops at the finest split: marching tetrahedra on a cone of tetrahedra from
// the cell's centre over its faces, each face cut by its lines into regions (convex: a
// chord cuts a convex polygon into two) and each region fanned from its centroid. The
// lines' vertices are the surface's own (value zero), every other vertex has a side, and
// each tetrahedron holds the centre and one region's points, so the surface in it is one
// triangle, through the line's vertices where the region meets a line: it meets the faces
// only along the lines, and the tetrahedra tile the cell.
namespace {
struct BPoint {
  Vec3f pos;
  std::uint32_t v;  // the mesh vertex of a line's point, else UINT32_MAX
  int side;         // 1 inside, 0 outside, -1 on a line
  int id;           // a corner 0..7, or a region's centroid 8 + k, or -1
};
}  // namespace

void CellMesher::coneCell(const Cell& cell) {
  double c[3];
  for (int a = 0; a < 3; ++a) c[a] = 0.5 * (cell.lo[a] + cell.hi[a]);
  const double cv = sampleAt(c[0], c[1], c[2]);
  const int sc = isInside(cv) ? 1 : 0;
  std::map<int, std::uint32_t> spokeVertex;  // corner or centroid id -> vertex on its spoke
  int centroids = 0;
  auto spoke = [&](const BPoint& x) {
    const auto it = spokeVertex.find(x.id);
    if (it != spokeVertex.end()) return it->second;
    const double b[3] = {x.pos[0], x.pos[1], x.pos[2]};
    const std::uint32_t v = newVertex(rootAlong(c, cv, b));
    spokeVertex[x.id] = v;
    return v;
  };
  auto corner = [&](int d) {
    BPoint p;
    for (int a = 0; a < 3; ++a)
      p.pos[a] = static_cast<float>((d >> a) & 1 ? cell.hi[a] : cell.lo[a]);
    p.v = UINT32_MAX;
    p.side = cell.inside[d] ? 1 : 0;
    p.id = d;
    return p;
  };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, cc = (a + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      const std::vector<Seg>& lines = cell.face[2 * a + side];
      // the face's boundary, counterclockwise seen from outside: corners and lines' ends
      static const int ccw[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      std::vector<BPoint> ring;
      for (int k = 0; k < 4; ++k) {
        const int i = side == 1 ? k : (4 - k) % 4, j = side == 1 ? (k + 1) % 4 : (4 - k + 3) % 4;
        const int d0 = (side << a) | (ccw[i][0] << b) | (ccw[i][1] << cc);
        const int d1 = (side << a) | (ccw[j][0] << b) | (ccw[j][1] << cc);
        const BPoint p = corner(d0), q = corner(d1);
        ring.push_back(p);
        int x = -1;
        for (int t = 0; t < 3; ++t)
          if (p.pos[t] != q.pos[t]) x = t;
        std::vector<std::pair<float, std::uint32_t>> on;
        for (const Seg& s : lines)
          for (std::uint32_t v : {s.from, s.to}) {
            const Vec3f& y = mesh_.positions[v];
            bool along = true;
            for (int t = 0; t < 3; ++t)
              if (t != x && y[t] != p.pos[t]) along = false;
            if (along) on.push_back({y[x], v});
          }
        std::sort(on.begin(), on.end());
        on.erase(std::unique(on.begin(), on.end()), on.end());
        if (q.pos[x] < p.pos[x]) std::reverse(on.begin(), on.end());
        for (const auto& [coord, v] : on) ring.push_back({mesh_.positions[v], v, -1, -1});
      }
      // chords: the lines chained from one boundary point to another
      std::unordered_map<std::uint32_t, std::uint32_t> next;
      std::unordered_set<std::uint32_t> onRing, hasPrev;
      for (const BPoint& p : ring)
        if (p.v != UINT32_MAX) onRing.insert(p.v);
      for (const Seg& s : lines) {
        next[s.from] = s.to;
        hasPrev.insert(s.to);
      }
      std::vector<std::vector<std::uint32_t>> chords;
      for (const Seg& s : lines) {
        if (!onRing.count(s.from)) continue;
        std::vector<std::uint32_t> chord = {s.from};
        std::uint32_t v = s.to;
        while (!onRing.count(v)) {
          chord.push_back(v);
          const auto it = next.find(v);
          if (it == next.end() || chord.size() > lines.size())
            throw Abort("a face's line does not end on its rim");
          v = it->second;
        }
        chord.push_back(v);
        chords.push_back(chord);
      }
      // regions: the ring split chord by chord; the region on a chord's right is inside
      struct Region {
        std::vector<BPoint> poly;
        int side;
      };
      std::vector<Region> regions = {{ring, -1}};
      for (const auto& chord : chords) {
        bool done = false;
        for (std::size_t r = 0; r < regions.size() && !done; ++r) {
          auto& poly = regions[r].poly;
          int ia = -1, ib = -1;
          for (std::size_t i = 0; i < poly.size(); ++i) {
            if (poly[i].v == chord.front()) ia = static_cast<int>(i);
            if (poly[i].v == chord.back()) ib = static_cast<int>(i);
          }
          if (ia < 0 || ib < 0) continue;
          // from A round to B, closed by the chord back: on the chord's right (inside)
          std::vector<BPoint> right, left;
          for (int i = ia;; i = (i + 1) % static_cast<int>(poly.size())) {
            right.push_back(poly[i]);
            if (i == ib) break;
          }
          for (std::size_t k = chord.size() - 2; k >= 1; --k)
            right.push_back({mesh_.positions[chord[k]], chord[k], -1, -1});
          for (int i = ib;; i = (i + 1) % static_cast<int>(poly.size())) {
            left.push_back(poly[i]);
            if (i == ia) break;
          }
          for (std::size_t k = 1; k + 1 < chord.size(); ++k)
            left.push_back({mesh_.positions[chord[k]], chord[k], -1, -1});
          regions[r] = {right, 1};
          regions.push_back({left, 0});
          done = true;
        }
        if (!done) throw Abort("a face's lines cross");
      }
      for (Region& r : regions) {
        // its side: its corners' (and the chords' sides must agree)
        int s = -1;
        for (const BPoint& p : r.poly)
          if (p.side >= 0) {
            if (s >= 0 && p.side != s) throw Abort("a face region holds both sides");
            s = p.side;
          }
        if (s < 0) s = r.side;
        if (s < 0) throw Abort("a face region has no side");
        if (r.side >= 0 && r.side != s) throw Abort("a face region's side disagrees");
        // its centroid, in the face's plane
        double m[3] = {0, 0, 0};
        for (const BPoint& p : r.poly)
          for (int t = 0; t < 3; ++t) m[t] += p.pos[t];
        BPoint cen;
        for (int t = 0; t < 3; ++t) cen.pos[t] = static_cast<float>(m[t] / r.poly.size());
        cen.pos[a] = static_cast<float>(side ? cell.hi[a] : cell.lo[a]);
        cen.v = UINT32_MAX;
        cen.side = s;
        cen.id = 8 + centroids++;
        for (std::size_t i = 0; i < r.poly.size(); ++i) {
          const BPoint& p = r.poly[i];
          const BPoint& q = r.poly[(i + 1) % r.poly.size()];
          // the fan triangle must wind as the face does (counterclockwise from outside)
          const double u0 = double(p.pos[b]) - cen.pos[b], u1 = double(p.pos[cc]) - cen.pos[cc];
          const double w0 = double(q.pos[b]) - cen.pos[b], w1 = double(q.pos[cc]) - cen.pos[cc];
          const double turn = (u0 * w1 - u1 * w0) * (side ? 1.0 : -1.0);
          if (!(turn > 0.0)) throw Abort("a face region is not convex");
          if (s == sc) continue;
          // the surface in tetrahedron (centre, centroid, p, q)
          std::uint32_t t0 = spoke(cen);
          std::uint32_t t1 = p.side < 0 ? p.v : spoke(p);
          std::uint32_t t2 = q.side < 0 ? q.v : spoke(q);
          emitFacing(t0, t1, t2, c, sc, cen.pos);
        }
      }
    }
  }
}

// Triangle (a, b, c), turned to face from the inside to the outside: away from the centre
// `o` when it is inside, towards it when not (`toward` lies on the other side from o).
void CellMesher::emitFacing(std::uint32_t a, std::uint32_t b, std::uint32_t c, const double o[3],
                            int so, const Vec3f& toward) {
  const Vec3f& A = mesh_.positions[a];
  const Vec3f& B = mesh_.positions[b];
  const Vec3f& C = mesh_.positions[c];
  double u[3], w[3], n[3], d[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = double(B[k]) - A[k];
    w[k] = double(C[k]) - A[k];
    d[k] = double(toward[k]) - o[k];
  }
  n[0] = u[1] * w[2] - u[2] * w[1];
  n[1] = u[2] * w[0] - u[0] * w[2];
  n[2] = u[0] * w[1] - u[1] * w[0];
  const double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
  const double ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  if (!(nn > 1e-12 * uu * ww)) throw Abort("a cone triangle is degenerate");
  const double s = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
  if (s == 0.0) throw Abort("a cone triangle faces no way");
  if ((s > 0.0) == (so == 1))
    added_.push_back({a, b, c});
  else
    added_.push_back({a, c, b});
}

// The vertex on the segment from a (value fa) to b: Illinois where the field changes sign,
// else off the middle; kept off both ends.
Vec3f CellMesher::rootAlong(const double a[3], double fa, const double b[3]) {
  IllinoisBracket r;
  r.fa = fa;
  r.fb = sampleAt(b[0], b[1], b[2]);
  double t = kNoRoot;
  if (isInside(r.fa) != isInside(r.fb)) {
    for (int it = 0; it < kMaxRootSteps && r.tb - r.ta > kRootBracket; ++it) {
      const double u = illinoisEstimate(r);
      t = u;
      const double v =
          sampleAt(a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1]), a[2] + u * (b[2] - a[2]));
      if (v == 0.0 || std::isnan(v)) break;
      illinoisUpdate(r, u, v);
    }
  }
  t = std::clamp(t, kEdgeMargin, 1.0 - kEdgeMargin);
  Vec3f p;
  for (int k = 0; k < 3; ++k) p[k] = static_cast<float>(a[k] + t * (b[k] - a[k]));
  return p;
}

// The vertex where line p-q crosses the plane x[m] = at (on the face with normal a), the
// same for both cells that share the line (computed from its lower-numbered end).
std::uint32_t CellMesher::cutVertex(std::uint32_t p, std::uint32_t q, int m, float at, int a) {
  const std::uint32_t lo = std::min(p, q), hi = std::max(p, q);
  const auto key = std::make_tuple(lo, hi, m);
  const auto it = cutVertex_.find(key);
  if (it != cutVertex_.end()) return it->second;
  const Vec3f P = mesh_.positions[lo], Q = mesh_.positions[hi];
  const double u = (double(at) - P[m]) / (double(Q[m]) - P[m]);
  Vec3f x;
  for (int k = 0; k < 3; ++k) x[k] = static_cast<float>(P[k] + u * (double(Q[k]) - P[k]));
  x[m] = at;
  x[a] = P[a];
  if (x == P || x == Q) throw Abort("a cut falls on a line's end");
  const std::uint32_t v = newVertex(x);
  cutVertex_[key] = v;
  return v;
}

// Records that line p-q now runs through `chain` (from p to q): every triangle with that
// edge takes them as vertices at the end.
void CellMesher::recordCuts(std::uint32_t p, std::uint32_t q, std::vector<std::uint32_t> chain) {
  if (chain.empty()) return;
  if (p > q) std::reverse(chain.begin(), chain.end());
  cuts_.emplace(undirected(p, q), std::move(chain));
}
std::uint64_t CellMesher::undirected(std::uint32_t a, std::uint32_t b) {
  return a < b ? dirKey(a, b) : dirKey(b, a);
}

void CellMesher::cutFace(int a, const std::vector<Seg>& segs, const float midF[3], FaceCut* out) {
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  // A line may pass a midline at a vertex (a finer level's face, which the level above cut
  // there when it split a cell): one piece ends there from one side and the next leaves to
  // the other. That vertex is the crossing. Any other line meeting a midline at an end (one
  // piece alone, or two on one side) is not handled.
  std::unordered_map<std::uint32_t, std::array<int, 4>> onMidline;  // pieces per midline side
  for (const Seg& s : segs)
    for (int end = 0; end < 2; ++end) {
      const std::uint32_t v = end ? s.to : s.from, w = end ? s.from : s.to;
      const Vec3f &x = mesh_.positions[v], &y = mesh_.positions[w];
      for (int k = 0; k < 2; ++k) {
        const int m = k ? c : b;
        if (x[m] != midF[m]) continue;
        if (y[m] == midF[m]) throw Abort("a line runs along a midline");
        auto it = onMidline.try_emplace(v, std::array<int, 4>{0, 0, 0, 0}).first;
        ++it->second[2 * k + (y[m] > midF[m] ? 1 : 0)];
      }
    }
  for (const auto& [v, count] : onMidline)
    for (int k = 0; k < 2; ++k) {
      if (count[2 * k] + count[2 * k + 1] == 0) continue;
      if (count[2 * k] != 1 || count[2 * k + 1] != 1) throw Abort("a line ends on a midline");
      const int m = k ? c : b, o = k ? b : c;
      const Vec3f& x = mesh_.positions[v];
      if (x[o] == midF[o]) throw Abort("a line passes a face's centre");
      out->halfMid[(m == b ? 0 : 2) + (x[o] > midF[o] ? 1 : 0)].push_back({x[o], v});
    }
  for (const Seg& s : segs) {
    const Vec3f p = mesh_.positions[s.from], q = mesh_.positions[s.to];
    std::vector<std::pair<double, int>> cuts;
    for (int m : {b, c}) {
      const float at = midF[m];
      if (p[m] != at && q[m] != at && (p[m] < at) != (q[m] < at))
        cuts.push_back({(double(at) - p[m]) / (double(q[m]) - p[m]), m});
    }
    std::sort(cuts.begin(), cuts.end());
    if (cuts.size() == 2 && cuts[0].first == cuts[1].first)
      throw Abort("a line passes a face's centre");
    std::vector<std::uint32_t> chain = {s.from};
    for (const auto& [u, m] : cuts) {
      const std::uint32_t v = cutVertex(s.from, s.to, m, midF[m], a);
      const Vec3f& x = mesh_.positions[v];
      const int o = m == b ? c : b;
      if (x[o] == midF[o]) throw Abort("a cut falls on a face's centre");
      chain.push_back(v);
      out->halfMid[(m == b ? 0 : 2) + (x[o] > midF[o] ? 1 : 0)].push_back({x[o], v});
    }
    chain.push_back(s.to);
    recordCuts(s.from, s.to, std::vector<std::uint32_t>(chain.begin() + 1, chain.end() - 1));
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
      const Vec3f& u = mesh_.positions[chain[i]];
      const Vec3f& w = mesh_.positions[chain[i + 1]];
      const double mb = 0.5 * (double(u[b]) + w[b]), mc = 0.5 * (double(u[c]) + w[c]);
      out->quarter[(mb > midF[b] ? 1 : 0) + (mc > midF[c] ? 2 : 0)].push_back(
          {chain[i], chain[i + 1]});
    }
  }
  for (auto& h : out->halfMid) std::sort(h.begin(), h.end());
}

void CellMesher::splitCell(const Cell& cell, int depth) {
  float loF[3], hiF[3], midF[3];
  double mid[3];
  for (int a = 0; a < 3; ++a) {
    loF[a] = static_cast<float>(cell.lo[a]);
    hiF[a] = static_cast<float>(cell.hi[a]);
    mid[a] = 0.5 * (cell.lo[a] + cell.hi[a]);
    midF[a] = static_cast<float>(mid[a]);
    if (!(loF[a] < midF[a] && midF[a] < hiF[a])) throw Abort("a cell is too small for float32");
  }
  auto pos = [&](int a, int d) { return d == 0 ? cell.lo[a] : d == 1 ? mid[a] : cell.hi[a]; };
  // sides at the 27 points (index d0 + 3 d1 + 9 d2), from the corners and the lines
  int sign[27];
  for (int& x : sign) x = -1;
  for (int d = 0; d < 8; ++d)
    sign[2 * (d & 1) + 3 * (d & 2) + 9 * ((d & 4) / 2)] = cell.inside[d] ? 1 : 0;
  // the cell's edges: the lines' ends on each, the midpoint's side by parity
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int e = 0; e < 4; ++e) {
      const int db = 2 * (e & 1), dc = 2 * (e >> 1);
      const float atB = db ? hiF[b] : loF[b], atC = dc ? hiF[c] : loF[c];
      std::vector<std::uint32_t> ends;
      for (const auto& f : cell.face)
        for (const Seg& s : f)
          for (std::uint32_t v : {s.from, s.to}) {
            const Vec3f& x = mesh_.positions[v];
            if (x[b] == atB && x[c] == atC) ends.push_back(v);
          }
      std::sort(ends.begin(), ends.end());
      ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
      int below = 0;
      for (std::uint32_t v : ends) {
        const float x = mesh_.positions[v][a];
        if (x == midF[a]) throw Abort("a line ends at an edge's midpoint");
        below += x < midF[a];
      }
      int d0[3], d2[3], d1[3];
      d0[a] = 0, d2[a] = 2, d1[a] = 1;
      d0[b] = d2[b] = d1[b] = db;
      d0[c] = d2[c] = d1[c] = dc;
      const int s0 = sign[d0[0] + 3 * d0[1] + 9 * d0[2]], s2 = sign[d2[0] + 3 * d2[1] + 9 * d2[2]];
      if ((s0 ^ static_cast<int>(ends.size() % 2)) != s2)
        throw Abort("a cell's edge is crossed inconsistently");
      sign[d1[0] + 3 * d1[1] + 9 * d1[2]] = s0 ^ (below % 2);
    }
  }
  // the faces: lines cut at the midlines, the centre's side by parity
  FaceCut cut[6];
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      FaceCut& fc = cut[2 * a + side];
      cutFace(a, cell.face[2 * a + side], midF, &fc);
      int centre = -1;
      for (int half = 0; half < 4; ++half) {
        int d[3];
        d[a] = 2 * side;
        const int along = half < 2 ? c : b, across = half < 2 ? b : c;
        d[across] = 1;
        d[along] = (half % 2) ? 2 : 0;
        const int end = sign[d[0] + 3 * d[1] + 9 * d[2]];
        const int x = end ^ static_cast<int>(fc.halfMid[half].size() % 2);
        if (centre >= 0 && x != centre) throw Abort("a cell's face centre has no one side");
        centre = x;
      }
      int d[3];
      d[a] = 2 * side;
      d[b] = d[c] = 1;
      sign[d[0] + 3 * d[1] + 9 * d[2]] = centre;
    }
  }
  // the centre, sampled; the six edges from it to the face centres
  const double centreValue = sampleAt(mid[0], mid[1], mid[2]);
  sign[13] = isInside(centreValue) ? 1 : 0;
  std::uint32_t spoke[6];  // vertex on the edge to face 2a + side, or UINT32_MAX
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      int d[3] = {1, 1, 1};
      d[a] = 2 * side;
      spoke[2 * a + side] = UINT32_MAX;
      if (sign[d[0] + 3 * d[1] + 9 * d[2]] == sign[13]) continue;
      double fp[3] = {mid[0], mid[1], mid[2]};
      fp[a] = side ? cell.hi[a] : cell.lo[a];
      spoke[2 * a + side] = newVertex(rootOnSegment(mid, centreValue, fp, a));
    }
  // the eight children
  for (int h = 0; h < 8; ++h) {
    const int hb[3] = {h & 1, (h >> 1) & 1, (h >> 2) & 1};
    Cell child;
    for (int a = 0; a < 3; ++a) {
      child.lo[a] = hb[a] ? mid[a] : cell.lo[a];
      child.hi[a] = hb[a] ? cell.hi[a] : mid[a];
    }
    for (int d = 0; d < 8; ++d) {
      const int i = (hb[0] + (d & 1)) + 3 * (hb[1] + ((d >> 1) & 1)) + 9 * (hb[2] + ((d >> 2) & 1));
      child.inside[d] = sign[i] == 1;
    }
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      for (int side = 0; side < 2; ++side) {
        std::vector<Seg>& out = child.face[2 * a + side];
        if (hb[a] == side) {  // on the cell's face: its pieces in this quarter
          out = cut[2 * a + side].quarter[hb[b] + 2 * hb[c]];
          continue;
        }
        // inside the cell (the plane through its centre): lines by the rule
        static const int ccw[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        int corner[4][3];
        for (int k = 0; k < 4; ++k) {
          const int i = side == 1 ? k : (4 - k) % 4;
          corner[k][a] = 1;
          corner[k][b] = hb[b] + ccw[i][0];
          corner[k][c] = hb[c] + ccw[i][1];
        }
        std::vector<WalkStep> walk;
        for (int k = 0; k < 4; ++k) {
          const int* p = corner[k];
          const int* q = corner[(k + 1) % 4];
          walk.push_back({true, sign[p[0] + 3 * p[1] + 9 * p[2]] == 1, 0});
          int x = -1;
          for (int t = 0; t < 3; ++t)
            if (p[t] != q[t]) x = t;
          const int y = x == b ? c : b;  // the other in-plane axis
          std::vector<std::uint32_t> xs;
          const bool upper = std::max(p[x], q[x]) == 2;
          if (p[y] != 1) {  // on the cell's face (y, p[y] / 2), its midline across a
            const FaceCut& fc = cut[2 * y + p[y] / 2];
            const int half = (a == (y + 1) % 3 ? 0 : 2) + (upper ? 1 : 0);
            for (const auto& [coord, v] : fc.halfMid[half]) xs.push_back(v);
          } else {  // the edge from the centre to face (x, side)
            const std::uint32_t v = spoke[2 * x + (upper ? 1 : 0)];
            if (v != UINT32_MAX) xs.push_back(v);
          }
          if (q[x] < p[x]) std::reverse(xs.begin(), xs.end());
          for (std::uint32_t v : xs) walk.push_back({false, false, v});
        }
        double centre[3];
        for (int t = 0; t < 3; ++t) centre[t] = 0.5 * (pos(t, corner[0][t]) + pos(t, corner[2][t]));
        pairCrossings(walk, centre, &out);
      }
    }
    meshCell(child, depth + 1);
  }
}

// The lines across a face from its walk (corners counterclockwise seen from outside, each
// followed by the crossings on the edge to the next): each arc of one side is cut off, the
// inside ones unless there are over two crossings and the face's centre is inside.
void CellMesher::pairCrossings(const std::vector<WalkStep>& walk, const double centre[3],
                               std::vector<Seg>* out) {
  const std::size_t n = walk.size();
  std::vector<std::size_t> xs;
  for (std::size_t i = 0; i < n; ++i)
    if (!walk[i].corner) xs.push_back(i);
  if (xs.empty()) return;
  bool s = walk[0].inside;
  std::vector<int> arcAfter(n, -1);
  for (std::size_t i = 1; i <= n; ++i) {
    const WalkStep& st = walk[i % n];
    if (st.corner) {
      if (st.inside != s) throw Abort("a face is crossed inconsistently");
    } else {
      s = !s;
      arcAfter[i % n] = s ? 1 : 0;
    }
  }
  bool cutInside = true;
  if (xs.size() > 2) cutInside = !isInside(sampleAt(centre[0], centre[1], centre[2]));
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const std::size_t i = xs[k], j = xs[(k + 1) % xs.size()];
    const bool arcInside = arcAfter[i] == 1;
    if (arcInside != cutInside) continue;
    // inside arcs run from their start to their end; outside ones the other way
    if (arcInside)
      out->push_back({walk[i].v, walk[j].v});
    else
      out->push_back({walk[j].v, walk[i].v});
  }
}

double CellMesher::sampleAt(double x, double y, double z) {
  ++stats_.evaluations;
  return combine(field_.eval(x, y, z), g_.boxField(x, y, z));
}

// rootAlong on an edge along `axis`: the other coordinates exactly the edge's.
Vec3f CellMesher::rootOnSegment(const double a[3], double fa, const double b[3], int axis) {
  Vec3f p = rootAlong(a, fa, b);
  for (int k = 0; k < 3; ++k)
    if (k != axis) p[k] = static_cast<float>(a[k]);
  const float lo = static_cast<float>(std::min(a[axis], b[axis]));
  const float hi = static_cast<float>(std::max(a[axis], b[axis]));
  if (!(p[axis] > lo && p[axis] < hi)) throw Abort("a cell is too small for float32");
  return p;
}

std::vector<std::uint32_t> CellMesher::between(std::uint32_t u, std::uint32_t w) const {
  std::vector<std::uint32_t> r;
  const auto it = cuts_.find(undirected(u, w));
  if (it == cuts_.end()) return r;
  std::vector<std::uint32_t> list = it->second;
  if (u > w) std::reverse(list.begin(), list.end());
  std::uint32_t prev = u;
  for (std::uint32_t v : list) {
    const std::vector<std::uint32_t> sub = between(prev, v);
    r.insert(r.end(), sub.begin(), sub.end());
    r.push_back(v);
    prev = v;
  }
  const std::vector<std::uint32_t> sub = between(prev, w);
  r.insert(r.end(), sub.begin(), sub.end());
  return r;
}

}  // namespace frep::refinement

#include "frep/strut_cells.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>

#include "base/errors.h"

namespace frep {

namespace {

// Every pair of the points at exactly this squared distance (up to rounding) as a strut.
void joinAtDistance(const std::vector<Vec3>& points, double squared, std::vector<UnitStrut>& out) {
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = i + 1; j < points.size(); ++j) {
      const Vec3 d = vsub(points[i], points[j]);
      if (std::abs(vdot(d, d) - squared) < 1e-9) out.push_back({points[i], points[j]});
    }
}

UnitCell simpleCubic() {
  UnitCell c{"simple_cubic", "struts along the cube's edges", {}, {{0, 0, 0}}};
  for (int a = 0; a < 3; ++a) {
    Vec3 e{0, 0, 0};
    e[a] = 1;
    c.struts.push_back({{0, 0, 0}, e});
  }
  return c;
}

UnitCell bcc() {
  UnitCell c{"bcc", "struts from the cube's centre to its eight corners", {}, {}};
  c.nodes = {{0, 0, 0}, {0.5, 0.5, 0.5}};
  for (int i = 0; i < 8; ++i)
    c.struts.push_back({{0.5, 0.5, 0.5}, {double(i & 1), double((i >> 1) & 1), double(i >> 2)}});
  return c;
}

// The diagonals of the faces x = 0, y = 0 and z = 0 (the other three are the next cells').
std::vector<UnitStrut> faceDiagonals() {
  std::vector<UnitStrut> s;
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    Vec3 p{0, 0, 0}, q{0, 0, 0}, r{0, 0, 0}, t{0, 0, 0};
    q[u] = q[v] = 1;  // (0,0) -> (1,1) in the face
    r[u] = 1;         // (1,0) -> (0,1)
    t[v] = 1;
    s.push_back({p, q});
    s.push_back({r, t});
  }
  return s;
}

std::vector<Vec3> faceCentres() {
  std::vector<Vec3> centres;
  for (int a = 0; a < 3; ++a)
    for (double side : {0.0, 1.0}) {
      Vec3 c{0.5, 0.5, 0.5};
      c[a] = side;
      centres.push_back(c);
    }
  return centres;
}

UnitCell fcc() {
  UnitCell c{"fcc", "struts along the diagonals of the cube's faces", faceDiagonals(), {}};
  c.nodes = faceCentres();
  c.nodes.push_back({0, 0, 0});
  return c;
}

UnitCell octet() {
  UnitCell c{"octet",
             "the octet truss: the face diagonals and the octahedron joining the faces' "
             "centres (every node joined to its twelve nearest)",
             faceDiagonals(),
             {}};
  c.nodes = faceCentres();
  c.nodes.push_back({0, 0, 0});
  joinAtDistance(faceCentres(), 0.5, c.struts);
  return c;
}

// The edges of the truncated octahedra round the cell's two centres of a body-centred
// lattice (Kelvin's foam: the Voronoi cells of that lattice).
UnitCell kelvin() {
  UnitCell c{"kelvin",
             "Kelvin's foam: the edges of the truncated octahedra that tile space round the "
             "points of a body-centred lattice",
             {},
             {}};
  for (const Vec3& centre : {Vec3{0, 0, 0}, Vec3{0.5, 0.5, 0.5}}) {
    std::vector<Vec3> corners;
    const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (const auto& perm : perms)
      for (double s1 : {-1.0, 1.0})
        for (double s2 : {-1.0, 1.0}) {
          const double v[3] = {0.0, 0.25 * s1, 0.5 * s2};
          Vec3 p{0, 0, 0};
          for (int a = 0; a < 3; ++a) p[perm[a]] = centre[perm[a]] + v[a];
          corners.push_back(p);
        }
    joinAtDistance(corners, 0.125, c.struts);
    c.nodes.insert(c.nodes.end(), corners.begin(), corners.end());
  }
  return c;
}

// Diamond's bonds: each atom of the second face-centred lattice, a quarter diagonal along,
// joined to its four nearest of the first.
UnitCell diamond() {
  UnitCell c{"diamond",
             "the bonds of the diamond crystal: every node joined to four at "
             "tetrahedral angles",
             {},
             {}};
  const Vec3 first[4] = {{0, 0, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}, {0.5, 0.5, 0}};
  for (const Vec3& a : first) {
    const Vec3 atom = vadd(a, {0.25, 0.25, 0.25});
    c.nodes.push_back(a);
    c.nodes.push_back(atom);
    for (const Vec3& to : {Vec3{0, 0, 0}, Vec3{0.5, 0.5, 0}, Vec3{0.5, 0, 0.5}, Vec3{0, 0.5, 0.5}})
      c.struts.push_back({atom, vadd(a, to)});
  }
  c.mirrorSymmetric = false;  // (its mirrors are the {110} planes)
  c.tetrahedral = true;
  return c;
}

}  // namespace

bool clip(const Vec3& a, const Vec3& b, const Vec3& lo, const Vec3& hi, StrutPiece* piece,
          const std::vector<Vec3>& halfSpaces) {
  double t0 = 0.0, t1 = 1.0;
  const Vec3 d = vsub(b, a);
  for (const Vec3& n : halfSpaces) {  // n . (a + t d) >= 0
    const double at = vdot(n, a), along = vdot(n, d);
    if (along == 0.0) {
      if (at < 0.0) return false;
      continue;
    }
    const double t = -at / along;
    if (along > 0.0)
      t0 = std::max(t0, t);
    else
      t1 = std::min(t1, t);
    if (t0 > t1) return false;
  }
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (a[k] < lo[k] || a[k] > hi[k]) return false;
      continue;
    }
    double ta = (lo[k] - a[k]) / d[k], tb = (hi[k] - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  piece->a = vadd(a, vscale(d, t0));
  piece->b = t1 == 1.0 ? b : vadd(a, vscale(d, t1));
  if (t0 == 0.0) piece->a = a;
  return true;
}

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 e = vsub(b, a), d = vsub(p, a);
  const double l2 = vdot(e, e);
  const double t = l2 > 0.0 ? std::clamp(vdot(d, e) / l2, 0.0, 1.0) : 0.0;
  return vlength(vsub(d, vscale(e, t)));
}

namespace {

bool samePoint(const Vec3& p, const Vec3& q, double tolerance) {
  return std::abs(p[0] - q[0]) <= tolerance && std::abs(p[1] - q[1]) <= tolerance &&
         std::abs(p[2] - q[2]) <= tolerance;
}

}  // namespace

const std::vector<UnitCell>& unitCells() {
  static const std::vector<UnitCell> cells = {simpleCubic(), bcc(),    fcc(),
                                              octet(),       kelvin(), diamond()};
  return cells;
}

const UnitCell& unitCell(const std::string& id) {
  for (const UnitCell& c : unitCells())
    if (c.id == id) return c;
  std::string ids;
  for (const UnitCell& c : unitCells()) ids += (ids.empty() ? "" : ", ") + c.id;
  throw ModelError("unknown unit cell '" + id + "'; unit cells: " + ids);
}

namespace {
double sampledCoveringRadius(const UnitCell& c) {
  // the network's struts round the cell (copies by -1, 0, 1 along each axis reach every point
  // of the cell closer than any further copy)
  std::vector<StrutPiece> near;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        for (const UnitStrut& s : c.struts) {
          const Vec3 t{double(i), double(j), double(k)};
          near.push_back({vadd(s.a, t), vadd(s.b, t)});
        }
  // The distance to the network is 1-Lipschitz: the farthest point lies within h sqrt(3) / 2
  // of a sample, so the sampled largest plus that bounds it.
  constexpr int n = 24;
  const double h = 1.0 / n;
  double largest = 0.0;
  for (int x = 0; x <= n; ++x)
    for (int y = 0; y <= n; ++y)
      for (int z = 0; z <= n; ++z) {
        const Vec3 p{x * h, y * h, z * h};
        double best = HUGE_VAL;
        for (const StrutPiece& s : near) best = std::min(best, distanceToSegment(p, s.a, s.b));
        largest = std::max(largest, best);
      }
  return largest + h * std::sqrt(3.0) / 2;
}
}  // namespace

double coveringRadius(const UnitCell& cell) {
  // (sampled once per cell and process, when first asked: a few milliseconds)
  static std::mutex lock;
  static std::map<std::string, double> radii;
  const std::lock_guard<std::mutex> hold(lock);
  auto found = radii.find(cell.id);
  if (found == radii.end()) found = radii.emplace(cell.id, sampledCoveringRadius(cell)).first;
  return found->second;
}

FoldedCell foldedCell(const UnitCell& cell, const Vec3& size, double blend) {
  FoldedCell f;
  using Fold = FoldedCell::Fold;
  const bool cube = size[0] == size[1] && size[1] == size[2];
  f.fold = blend > 0.0 ? Fold::Translate
           : cell.mirrorSymmetric
               ? Fold::Mirror
               : (cell.tetrahedral && cube ? Fold::Tetrahedral : Fold::Translate);
  // In cell coordinates (a clip to a box commutes with scaling the axes), so that the pieces
  // are the same for every cell size: the domain [0, 1/2]^3, or the cell grown by the
  // covering radius (and the blend; in world units, so per axis in cell units), cut to
  // x >= y >= |z| when folded by the tetrahedral mirrors too.
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};
  const double margin = f.fold == Fold::Mirror
                            ? 0.0
                            : coveringRadius(cell) * std::max({size[0], size[1], size[2]}) + blend;
  const double start = f.fold == Fold::Tetrahedral ? -0.5 : 0.0;
  std::vector<Vec3> halfSpaces;
  if (f.fold == Fold::Tetrahedral) halfSpaces = {{1, -1, 0}, {0, 1, -1}, {0, 1, 1}};
  int reach[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = start - margin / size[a];
    hi[a] = f.fold == Fold::Mirror ? 0.5 : start + 1.0 + margin / size[a];
    reach[a] =
        1 + static_cast<int>(std::ceil(std::max(-lo[a], hi[a] - 1.0)));  // copies that reach it
  }
  constexpr double same = 1e-12;
  std::vector<StrutPiece> pieces;
  std::vector<Vec3> nodes;
  for (int i = -reach[0]; i <= reach[0]; ++i)
    for (int j = -reach[1]; j <= reach[1]; ++j)
      for (int k = -reach[2]; k <= reach[2]; ++k) {
        const Vec3 t{double(i), double(j), double(k)};
        for (const UnitStrut& s : cell.struts) {
          StrutPiece piece;
          if (!clip(vadd(s.a, t), vadd(s.b, t), lo, hi, &piece, halfSpaces)) continue;
          if (piece.b < piece.a) std::swap(piece.a, piece.b);  // (one order, for the duplicates)
          const bool known = std::any_of(pieces.begin(), pieces.end(), [&](const StrutPiece& q) {
            return samePoint(q.a, piece.a, same) && samePoint(q.b, piece.b, same);
          });
          if (!known) pieces.push_back(piece);
        }
        for (const Vec3& n : cell.nodes) {
          const Vec3 p = vadd(n, t);
          bool inside = true;
          for (int a = 0; a < 3; ++a)
            inside = inside && p[a] >= lo[a] - same && p[a] <= hi[a] + same;
          for (const Vec3& n : halfSpaces) inside = inside && vdot(n, p) >= -same;
          if (inside && std::none_of(nodes.begin(), nodes.end(),
                                     [&](const Vec3& q) { return samePoint(q, p, same); }))
            nodes.push_back(p);
        }
      }
  auto world = [&](const Vec3& u) { return Vec3{u[0] * size[0], u[1] * size[1], u[2] * size[2]}; };
  // a piece that is one point (a strut touching the domain) where another piece reaches adds
  // nothing
  for (const StrutPiece& p : pieces) {
    const bool point = samePoint(p.a, p.b, same);
    const bool covered =
        point && std::any_of(pieces.begin(), pieces.end(), [&](const StrutPiece& q) {
          return !samePoint(q.a, q.b, same) && distanceToSegment(p.a, q.a, q.b) <= same;
        });
    if (!covered) f.pieces.push_back({world(p.a), world(p.b)});
  }
  for (const Vec3& n : nodes) f.nodes.push_back(world(n));
  return f;
}

std::vector<StrutPiece> strutsInBox(const UnitCell& cell, const Vec3& size, const Vec3& origin,
                                    const Box3& box) {
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {  // the cells whose struts may reach the box (struts reach a cell)
    lo[a] = static_cast<std::int64_t>(std::floor((box.lo[a] - origin[a]) / size[a])) - 1;
    hi[a] = static_cast<std::int64_t>(std::floor((box.hi[a] - origin[a]) / size[a])) + 1;
  }
  auto world = [&](const Vec3& u, std::int64_t i, std::int64_t j, std::int64_t k) {
    return Vec3{origin[0] + (u[0] + double(i)) * size[0], origin[1] + (u[1] + double(j)) * size[1],
                origin[2] + (u[2] + double(k)) * size[2]};
  };
  // (a cell's struts may repeat another's where polyhedra share an edge: Kelvin's foam)
  std::vector<UnitStrut> own;
  for (const UnitStrut& s : cell.struts) {
    UnitStrut t = s;
    if (t.b < t.a) std::swap(t.a, t.b);
    if (std::none_of(own.begin(), own.end(), [&](const UnitStrut& o) {
          return samePoint(o.a, t.a, 1e-12) && samePoint(o.b, t.b, 1e-12);
        }))
      own.push_back(t);
  }
  std::vector<StrutPiece> out;
  std::map<std::pair<Vec3, Vec3>, bool> seen;  // (copies of one strut by different cells)
  for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
    for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
      for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
        for (const UnitStrut& s : own) {
          StrutPiece p{world(s.a, i, j, k), world(s.b, i, j, k)};
          bool meets = true;
          for (int a = 0; a < 3; ++a)
            meets = meets && std::min(p.a[a], p.b[a]) <= box.hi[a] &&
                    std::max(p.a[a], p.b[a]) >= box.lo[a];
          if (!meets) continue;
          // the same strut from two cells (one whose end lies on a cell's face) once
          const Vec3 ua = vadd(s.a, {double(i), double(j), double(k)});
          const Vec3 ub = vadd(s.b, {double(i), double(j), double(k)});
          if (!seen.emplace(std::make_pair(ua, ub), true).second) continue;
          out.push_back(p);
        }
  return out;
}

}  // namespace frep

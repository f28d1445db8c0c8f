// Sphere sweep: a sphere of a radius varying linearly along a polyline, swept along it (seed
// 000's sphere sweep, HyperFun's hfConvLine shape without the convolution). The field is
// the exact distance to the polyline subtracted from the radius, so it is a distance field
// for a constant radius; with a varying one each segment is a tapered capsule.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "frep/node_helpers.h"
#include "frep/registry.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"

namespace frep {

namespace {

// A path of 100,000 points compiled to two million instructions, and the octree's region
// specialisation over them took minutes before the first brick (10,000 take about 10 s).
constexpr std::size_t kMostPathPoints = 10001;

// r(t) - |p - (a + t (b - a))| with t the clamped projection of p on the segment [a, b].
Slot capsule(ProgramBuilder& b, const Point3Slots& p, const Vec3& a, const Vec3& e, double ra,
             double rb) {
  Slot t;
  const Slot dist = segmentDistance(b, p, a, e, &t);
  if (e[0] == 0.0 && e[1] == 0.0 && e[2] == 0.0) return b.sub(b.constant(ra), dist);
  return b.affine(t, dist, dist, rb - ra, -1.0, 0.0, ra);
}

// One piece of the path: a straight segment or a circular arc, with the arc length at its
// start and end (for the radius).
struct Piece {
  bool arc = false;
  Vec3 a, b;                         // start and end
  Vec3 centre, mid, across, normal;  // arc: centre and frame (mid: towards the arc's middle)
  double radius = 0, half = 0;       // arc: radius and half the angle it spans
  double s0 = 0, s1 = 0;             // arc length at the start and end
};

Vec3 minus(const Vec3& p, const Vec3& q) {
  return {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
}
double dot(const Vec3& p, const Vec3& q) {
  return p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
}
Vec3 scaled(const Vec3& p, double k) {
  return {p[0] * k, p[1] * k, p[2] * k};
}
Vec3 plus(const Vec3& p, const Vec3& q) {
  return {p[0] + q[0], p[1] + q[1], p[2] + q[2]};
}

// The arc from a through m to b; a straight segment from a to b when the three are collinear.
Piece arcThrough(const Vec3& a, const Vec3& m, const Vec3& b) {
  Piece p;
  p.a = a;
  p.b = b;
  const Vec3 ab = minus(m, a), ac = minus(b, a), n = cross(ab, ac);
  const double n2 = dot(n, n);
  if (n2 <= 1e-24 * dot(ab, ab) * dot(ac, ac)) return p;  // collinear: a segment
  p.arc = true;
  // circumcentre: a + (|ac|^2 (n x ab) + |ab|^2 (ac x n)) / (2 |n|^2)
  p.centre = plus(
      a,
      scaled(plus(scaled(cross(n, ab), dot(ac, ac)), scaled(cross(ac, n), dot(ab, ab))), 0.5 / n2));
  const Vec3 ra = minus(a, p.centre);
  p.radius = std::sqrt(dot(ra, ra));
  p.normal = scaled(n, 1.0 / std::sqrt(n2));  // a -> m -> b turns counter-clockwise about it
  const Vec3 u = scaled(ra, 1.0 / p.radius), v = cross(p.normal, u);
  const Vec3 rb = minus(b, p.centre);
  double span = std::atan2(dot(rb, v), dot(rb, u));
  if (span <= 0) span += 2 * kPi;
  p.half = span / 2;
  p.mid = plus(scaled(u, std::cos(p.half)), scaled(v, std::sin(p.half)));
  p.across = cross(p.normal, p.mid);
  return p;
}

double pieceLength(const Piece& p) {
  if (p.arc) return 2 * p.half * p.radius;
  const Vec3 e = minus(p.b, p.a);
  return std::sqrt(dot(e, e));
}

// A point of the clamped uniform B-spline of degree min(3, n - 1) with these control points
// at t in [0, 1] (de Boor's algorithm).
Vec3 bsplineAt(const std::vector<Vec3>& ctrl, double t) {
  const int n = static_cast<int>(ctrl.size()), p = std::min(3, n - 1), spans = n - p;
  auto knot = [&](int i) { return i <= p ? 0.0 : i >= n ? 1.0 : double(i - p) / spans; };
  int k = p + std::min(spans - 1, static_cast<int>(t * spans));  // t in [knot(k), knot(k+1))
  std::vector<Vec3> d(ctrl.begin() + (k - p), ctrl.begin() + k + 1);
  for (int r = 1; r <= p; ++r)
    for (int j = p; j >= r; --j) {
      const int i = j + k - p;
      const double den = knot(i + p - r + 1) - knot(i);
      const double a = den > 0 ? (t - knot(i)) / den : 0.0;
      for (int c = 0; c < 3; ++c) d[j][c] = (1 - a) * d[j - 1][c] + a * d[j][c];
    }
  return d[p];
}

// The B-spline as a polyline whose chords stay within `tolerance` of the curve (a chord is
// halved until its middle is that close; the curve lies in its control polygon's hull).
std::vector<Vec3> bsplinePolyline(const std::vector<Vec3>& ctrl, double tolerance) {
  std::vector<Vec3> out = {ctrl.front()};
  const int pieces = 8 * static_cast<int>(ctrl.size());
  std::function<void(double, const Vec3&, double, const Vec3&, int)> split =
      [&](double t0, const Vec3& a, double t1, const Vec3& b, int depth) {
        const double tm = 0.5 * (t0 + t1);
        const Vec3 m = bsplineAt(ctrl, tm);
        const Vec3 chord = {0.5 * (a[0] + b[0]) - m[0], 0.5 * (a[1] + b[1]) - m[1],
                            0.5 * (a[2] + b[2]) - m[2]};
        if (depth < 20 && std::sqrt(dot(chord, chord)) > tolerance) {
          split(t0, a, tm, m, depth + 1);
          split(tm, m, t1, b, depth + 1);
        } else {
          out.push_back(b);
        }
      };
  Vec3 prev = ctrl.front();
  for (int i = 1; i <= pieces; ++i) {
    const double t = double(i) / pieces;
    const Vec3 q = i == pieces ? ctrl.back() : bsplineAt(ctrl, t);
    split(double(i - 1) / pieces, prev, t, q, 0);
    prev = q;
  }
  return out;
}

// Sampling tolerance of a B-spline path: 1e-4 of its control polygon's size (finer costs
// instructions: about 70 pieces for a simple cubic).
double bsplineTolerance(const std::vector<Vec3>& ctrl) {
  const Box3 b = pointsBounds(ctrl, 0.0);
  const Vec3 d = minus(b.hi, b.lo);
  return 1e-4 * std::max(std::sqrt(dot(d, d)), 1e-12);
}

// The pieces of the path; `arcs`: the points are start, middle, end of each arc in turn.
std::vector<Piece> piecesOf(const std::vector<Vec3>& pts, bool arcs) {
  std::vector<Piece> pieces;
  if (arcs) {
    for (std::size_t i = 0; i + 2 < pts.size(); i += 2)
      pieces.push_back(arcThrough(pts[i], pts[i + 1], pts[i + 2]));
  } else {
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
      Piece p;
      p.a = pts[i];
      p.b = pts[i + 1];
      pieces.push_back(p);
    }
  }
  double s = 0;
  for (Piece& p : pieces) {
    p.s0 = s;
    s += pieceLength(p);
    p.s1 = s;
  }
  return pieces;
}

// r(theta) - dist(p, circle) where p's closest circle point is on the arc (|theta| <= half,
// theta measured from the arc's middle), else the spheres at its ends.
Slot arcTube(ProgramBuilder& b, const Point3Slots& p, const Piece& a, double ra, double rb) {
  const Vec3& c = a.centre;
  auto along = [&](const Vec3& d) { return b.affine(p.x, p.y, p.z, d[0], d[1], d[2], -dot(d, c)); };
  const Slot x = along(a.mid), y = along(a.across), h = along(a.normal);
  const Slot rho = b.length2(x, y);
  const Slot theta = b.emit(Op::Atan2, y, x);
  const Slot toCircle = b.length2(b.affine(rho, rho, rho, 1.0, 0, 0, -a.radius), h);
  // the radius goes linearly with the arc length, so with theta
  const double slope = (rb - ra) / (2 * a.half);
  const Slot onArc = b.affine(theta, toCircle, toCircle, slope, -1.0, 0, ra + slope * a.half);
  auto ball = [&](const Vec3& q, double r) {
    return b.sub(b.constant(r), b.length3(b.affine(p.x, p.x, p.x, 1, 0, 0, -q[0]),
                                          b.affine(p.y, p.y, p.y, 1, 0, 0, -q[1]),
                                          b.affine(p.z, p.z, p.z, 1, 0, 0, -q[2])));
  };
  const Slot ends = b.max(ball(a.a, ra), ball(a.b, rb));
  const Slot inRange = b.affine(b.abs(theta), theta, theta, -1.0, 0, 0, a.half);
  return b.emit(Op::Select, inRange, onArc, ends);
}

std::string arcProblem(const std::vector<Vec3>& pts) {
  if (pts.size() % 2 == 0)
    return "parameter 'points' has " + std::to_string(pts.size()) +
           " points; with segments \"arcs\" it needs an odd number: start, middle and end of "
           "each arc, the end starting the next";
  for (std::size_t i = 0; i + 2 < pts.size(); i += 2) {
    const Vec3 d = minus(pts[i + 2], pts[i]), m = minus(pts[i + 1], pts[i]);
    if (dot(d, d) <= 1e-24 * (1 + dot(m, m)))
      return "parameter 'points': arc " + std::to_string(i / 2) +
             " starts and ends at the same point; split a full circle into two arcs";
  }
  return "";
}

}  // namespace

void registerSweeps(Registry& r) {
  ParamTemplate r1 = positiveLength("radius1", 0.2, "Radius at the first point.");
  ParamTemplate r2 = realParam("radius2", 0.2, "length", "Radius at the last point (0: a point).");
  range(r2, 0.0, kInf);
  ParamTemplate path = pointsParam("points", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, 2, "length",
                                   "The path, in order: the polyline's points, or with segments "
                                   "\"arcs\" the start, middle and end of each arc (at most "
                                   "10,001 points).");
  path.path = true;
  r.add({"sweep",
         "primitive",
         "A sphere swept along a path, its radius going linearly from radius1 to radius2 "
         "along the length. The path is a polyline, or with segments \"arcs\" a chain of "
         "circular arcs, each through three points (three collinear points make a straight "
         "piece), so lines and arcs are followed exactly. In FreeCAD the path comes from any "
         "edge, wire, sketch or Draft wire (property PointsSource): lines and arcs exactly "
         "with \"arcs\", other curves sampled to 1/1000 of their size. With \"bspline\" the "
         "points are the control points of a clamped uniform cubic B-spline, followed within "
         "1e-4 of the control polygon's size.",
         "F = max over the pieces of r(s) - dist(p, piece), s the arc length at the closest "
         "point; an arc: dist = sqrt((rho - R)^2 + h^2) where p's angle about the centre is "
         "within the arc, else the distance to its nearer end",
         0,
         0,
         {path, r1, r2,
          choiceParam("segments", {"lines", "arcs", "bspline"},
                      "How the points make the path: a polyline, arcs through three points "
                      "each, or the control points of a clamped cubic B-spline.")},
         [](CompileContext& c) {
           auto& b = c.b;
           const std::string& kind = c.param("segments").text;
           std::vector<Vec3> pts = pointsOf(c.param("points"));
           if (kind == "bspline") pts = bsplinePolyline(pts, bsplineTolerance(pts));
           const std::vector<Piece> pieces = piecesOf(pts, kind == "arcs");
           const double total = pieces.back().s1, ra = c.real("radius1"), rb = c.real("radius2");
           auto radiusAt = [&](double s) { return total > 0 ? ra + (rb - ra) * s / total : ra; };
           Slot field = 0;
           for (std::size_t i = 0; i < pieces.size(); ++i) {
             const Piece& p = pieces[i];
             const Slot f =
                 p.arc ? arcTube(b, c.p, p, radiusAt(p.s0), radiusAt(p.s1))
                       : capsule(b, c.p, p.a, minus(p.b, p.a), radiusAt(p.s0), radiusAt(p.s1));
             field = i == 0 ? f : b.max(field, f);
           }
           return field;
         },
         [](const Node& n, const std::vector<Box3>&) {
           const std::vector<Vec3> pts = pointsOf(n.param("points"));
           const double pad = std::max(n.real("radius1"), n.real("radius2"));
           Box3 box = pointsBounds(pts, pad);
           if (n.param("segments").text != "arcs") return box;
           for (const Piece& p : piecesOf(pts, true)) {
             if (!p.arc) continue;
             Vec3 half;  // the whole circle's box: R sqrt(1 - n_a^2) about each axis
             for (int a = 0; a < 3; ++a)
               half[a] = p.radius * std::sqrt(std::max(0.0, 1 - p.normal[a] * p.normal[a])) + pad;
             box = boxHull(box, boxAround(p.centre, half));
           }
           return box;
         },
         [](const Node& n) -> std::string {
           const std::size_t count = n.param("points").numbers.size() / 3;
           if (count > kMostPathPoints)
             return "parameter 'points' has " + std::to_string(count) + " points; at most " +
                    std::to_string(kMostPathPoints) +
                    " are allowed (each point of the mesh takes the nearest of the path's pieces "
                    "from those near its brick, and finding them costs the whole path at the "
                    "top of the octree); sample the path more coarsely";
           if (n.param("segments").text != "arcs") return "";
           return arcProblem(pointsOf(n.param("points")));
         }});
}

}  // namespace frep

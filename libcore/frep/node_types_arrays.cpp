// Linear and polar arrays: copies of the input along a step or around an axis, combined by
// union. Each point evaluates only the copy whose cell it is in and that copy's two
// neighbours (a one-dimensional spatial index by floor), so ten thousand copies cost three
// evaluations of the input, not ten thousand. Exact as long as a copy does not reach past
// its neighbours' cells; a copy reaching further is cut there.
#include <algorithm>
#include <cmath>
#include <limits>

#include "frep/bounds.h"
#include "base/errors.h"
#include "frep/instances.h"
#include "frep/node_helpers.h"
#include "frep/registry.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"

namespace frep {

namespace {

// Where the input is, to centre the cells on its copies (the origin when unknown).
Vec3 inputCentre(const CompileContext& c) {
  const Box3 b = structuralBounds(c.node().inputs.at(0));
  Vec3 m{0, 0, 0};
  for (int a = 0; a < 3; ++a)
    if (std::isfinite(b.lo[a]) && std::isfinite(b.hi[a])) m[a] = 0.5 * (b.lo[a] + b.hi[a]);
  return m;
}

// The copy a point in cell t looks at: k + shift, k = floor(t + 0.5) clamped to the row
// first, so that beyond an end the point still sees the end copy and its neighbour.
Slot copyIndex(ProgramBuilder& b, Slot t, double shift, int count, bool wrap) {
  Slot k = b.emit(Op::Floor, b.affine(t, t, t, 1.0, 0, 0, 0.5));
  if (wrap) return b.affine(k, t, t, 1.0, 0, 0, shift);  // a full circle: rotations are periodic
  const Slot last = b.constant(count - 1.0), zero = b.constant(0.0);
  k = b.min(b.max(k, zero), last);
  return b.min(b.max(b.affine(k, t, t, 1.0, 0, 0, shift), zero), last);
}

// An unbounded copy reaches every point, so each point evaluates every copy: at most this
// many (a bounded copy is found through the index and takes any number).
constexpr std::size_t kMostUnboundedCopies = 1000;

// Where the copied solid is: its structural box, else the box interval arithmetic finds;
// unknownBounds() for an unbounded solid (every copy then reaches everywhere, and the
// export's box clips the result). Returns "" or what is wrong with it as the input of
// `copies` copies.
std::string copiedSolidBox(const NodePtr& input, std::size_t copies, Box3* box) {
  *box = structuralBounds(input);
  if (isFinite(*box)) return "";
  BoundsOptions o;
  o.known = *box;
  const SolidBounds b = findBounds(compile(input), o);
  if (b.empty) return "the copied solid (input 0) is empty";
  if (b.bounded()) {
    *box = b.box;
    return "";
  }
  *box = unknownBounds();
  if (copies > kMostUnboundedCopies)
    return "the copied solid (input 0) is unbounded, so every point evaluates every copy; "
           "at most " + std::to_string(kMostUnboundedCopies) + " copies of it are allowed, got " +
           std::to_string(copies) + " (intersect it with a box to copy it more often)";
  return "";
}

// The radius round the origin beyond which the copied solid's field is negative (infinite
// for an unbounded solid).
double reachOf(const Box3& b) {
  if (!isFinite(b)) return std::numeric_limits<double>::infinity();
  double r2 = 0;
  for (int a = 0; a < 3; ++a) r2 += sqr(std::max(std::abs(b.lo[a]), std::abs(b.hi[a])));
  return std::sqrt(r2);
}

// How copies combine, shared by the arrays and the instancer.
std::vector<ParamTemplate> combineParams() {
  ParamTemplate amount = realParam("blend_amount", 0.1, "length",
                                   "combine = blend: how much material the blend adds (a0).");
  range(amount, 0.0, kInf);
  return {choiceParam("combine", {"union", "blend"}, "How the copies combine."), amount,
          positiveLength("blend_range", 0.1,
                         "combine = blend: how far from each copy the blend reaches (a1).")};
}

std::vector<ParamTemplate> withCombine(std::vector<ParamTemplate> params) {
  for (const ParamTemplate& p : combineParams()) params.push_back(p);
  return params;
}

// Where one copy can add material: its own box for a union. A blend adds at most a0, so its
// solid lies where some copy has f >= -a0: the box of the input offset by a0, found by
// interval arithmetic (unknown when that fails).
Box3 copyBox(const Node& n, const Box3& input) {
  const double a0 = n.real("blend_amount");
  if (n.param("combine").text != "blend" || a0 == 0.0) return input;
  const NodePtr grown =
      makeNode("offset", {{"distance", realValue(a0)}}, {n.inputs.at(0)}, "blend reach");
  const SolidBounds b = findBounds(compile(grown));
  return b.bounded() ? b.box : unknownBounds();
}

constexpr double kNoCopy = -1e300;  // a value below every field: no copy there

// The three nearest copies of an array, v[0..2] at indices j[0..2]: union, or Pasko's blend
// of the largest two (m1 + a0 / (1 + (m1/a1)^2 + (m2/a1)^2)). A neighbour index equal to the
// middle one (a row's clamped end) repeats a copy; for the blend it must not count twice.
Slot combineThree(CompileContext& c, const Slot v[3], const Slot j[3], bool lastRepeatsFirst) {
  auto& b = c.b;
  if (c.param("combine").text != "blend") return b.max(b.max(v[0], v[1]), v[2]);
  const Slot none = b.constant(kNoCopy);
  const Slot lo = b.emit(Op::Select, b.affine(j[1], j[0], j[0], 1, -1, 0, -0.5), v[0], none);
  const Slot hi = lastRepeatsFirst
                      ? none
                      : b.emit(Op::Select, b.affine(j[2], j[1], j[1], 1, -1, 0, -0.5), v[2], none);
  const Slot m1 = b.max(b.max(lo, v[1]), hi);
  const Slot m2 = b.max(b.min(lo, v[1]), b.min(b.max(lo, v[1]), hi));  // the second largest
  const double a1 = c.real("blend_range");
  return b.add(m1, b.emit(Op::BlendBump, m1, m2, 0, {c.real("blend_amount"), a1, a1}));
}

// The instancer's rotations as matrices: none, or one per position (a rotation vector: axis
// times angle in degrees).
std::vector<std::array<double, 9>> rotationsOf(const Node& n) {
  std::vector<std::array<double, 9>> out;
  for (const Vec3& v : pointsOf(n.param("rotations"))) {
    const double angle = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const Mat34 m = angle > 0 ? rotationMatrix(v, angle, {0, 0, 0})
                              : Mat34{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    out.push_back({m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]});
  }
  return out;
}

}  // namespace

void registerArrays(Registry& r) {
  {
    ParamTemplate positions = pointsParam(
        "positions", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, 1, "length",
        "Where the copies go: the input's origin is moved to each point.");
    ParamTemplate rotations = pointsParam(
        "rotations", {}, 0, "",
        "How each copy is turned about the input's origin before it is moved: a rotation "
        "vector per position (axis times angle in degrees), or none at all.");
    rotations.follows = "positions";
    r.add({"instancer",
           "array",
           "Copies of the input at a list of points, combined by union or blend. In FreeCAD "
           "the points can come from mesh vertices, a point cloud, a sketch's or Draft "
           "object's vertices or the copies of a Draft array (property PositionsSource). A "
           "point evaluates only the copies within reach, found with a k-d tree, so 10,000 "
           "copies cost a few evaluations of the input. Model the input around the origin. "
           "Copies may be turned (`rotations`; from a Draft array, its copies' rotations).",
           "N(p) = the copies c_i within reach of p (reach: the input's bounding radius), "
           "else the nearest;  union: F = max_(i in N(p)) f(R_i^T (p - c_i));  blend: the "
           "largest two m1 >= m2, F = m1 + a0 / (1 + (m1/a1)^2 + (m2/a1)^2)",
           1,
           1,
           withCombine({positions, rotations}),
           [](CompileContext& c) {
             Box3 box;
             const std::string problem = copiedSolidBox(
                 c.node().inputs.at(0), c.node().param("positions").numbers.size() / 3, &box);
             if (!problem.empty()) throw ModelError("instancer: " + problem);
             auto copy = std::make_shared<const Program>(compile(c.node().inputs.at(0)));
             const bool blend = c.param("combine").text == "blend";
             auto set = std::make_shared<const InstanceSet>(
                 pointsOf(c.param("positions")), rotationsOf(c.node()), std::move(copy),
                 reachOf(box),
                 blend ? InstanceSet::Combine::Blend : InstanceSet::Combine::Union,
                 InstanceSet::Blend{c.real("blend_amount"), c.real("blend_range")});
             return c.b.external(std::move(set), c.p.x, c.p.y, c.p.z);
           },
           [](const Node& n, const std::vector<Box3>& in) {
             const Box3 at = pointsBounds(pointsOf(n.param("positions")), 0.0);
             Box3 b = copyBox(n, in[0]);
             if (!n.param("rotations").numbers.empty()) {
               // a turned copy stays within its reach of its position
               if (!isFinite(b)) return unknownBounds();
               const double reach = reachOf(b);
               b = boxAround({0, 0, 0}, {reach, reach, reach});
             }
             for (int a = 0; a < 3; ++a) {
               b.lo[a] += at.lo[a];
               b.hi[a] += at.hi[a];
             }
             return b;
           },
           [](const Node& n) {
             const std::size_t turns = n.param("rotations").numbers.size() / 3,
                               at = n.param("positions").numbers.size() / 3;
             if (turns != 0 && turns != at)
               return "parameter 'rotations' has " + std::to_string(turns) +
                      " rotations for " + std::to_string(at) + " positions; give one per " +
                      "position or none";
             Box3 box;
             return copiedSolidBox(n.inputs.at(0), at, &box);
           }});
  }

  {
    ParamTemplate count = intParam("count", 3, "Number of copies, the input included.");
    range(count, 1, 1000000);
    ParamTemplate step = vec3Param("step", {1, 0, 0}, "length", "From one copy to the next.");
    step.nonZeroVector = true;
    r.add({"linear_array",
           "array",
           "Copies of the input in a row, `step` apart, combined by union or blend (HyperFun's "
           "and Draft's linear array).",
           "k = clamp(round((p - m).step / |step|^2), 0, count-1);  F = max_(j = k-1..k+1, "
           "clamped) f(p - j step), or the blend of the largest two",
           1,
           1,
           withCombine({count, step}),
           [](CompileContext& c) {
             auto& b = c.b;
             const int n = static_cast<int>(c.real("count"));
             if (n == 1) return c.input(0);
             const Vec3 s = c.vec3("step"), m = inputCentre(c);
             const double l2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
             const Slot t = b.affine(c.p.x, c.p.y, c.p.z, s[0] / l2, s[1] / l2, s[2] / l2,
                                     -(s[0] * m[0] + s[1] * m[1] + s[2] * m[2]) / l2);
             Slot v[3], j[3];
             for (int d = -1; d <= 1; ++d) {
               j[d + 1] = copyIndex(b, t, d, n, false);
               const Point3Slots q = {b.affine(c.p.x, j[d + 1], j[d + 1], 1.0, -s[0], 0, 0),
                                      b.affine(c.p.y, j[d + 1], j[d + 1], 1.0, -s[1], 0, 0),
                                      b.affine(c.p.z, j[d + 1], j[d + 1], 1.0, -s[2], 0, 0)};
               v[d + 1] = c.input(0, q);
             }
             return combineThree(c, v, j, false);
           },
           [](const Node& n, const std::vector<Box3>& in) {
             const Vec3 s = n.vec3("step");
             const double last = n.real("count") - 1;
             const Box3 one = copyBox(n, in[0]);
             return boxHull(one, affineImage({1, 0, 0, last * s[0], 0, 1, 0, last * s[1], 0, 0, 1,
                                              last * s[2]},
                                             one));
           }});
  }

  {
    ParamTemplate count = intParam("count", 6, "Number of copies, the input included.");
    range(count, 1, 10000);
    ParamTemplate angle =
        realParam("angle", 360.0, "angle", "Angle the copies span; 360 spaces them all round.");
    range(angle, 0.0, 360.0, true);
    r.add({"polar_array",
           "array",
           "Copies of the input turned about an axis, combined by union or blend (Draft's "
           "polar array). With `angle` 360 they go all round, `count` of them evenly spaced; with "
           "less, the last copy is turned by `angle`.",
           "step = angle / count (360) or angle / (count - 1);  F = max over the three copies "
           "nearest p's angle of f(R(axis, -j step) (p - center) + center)",
           1,
           1,
           withCombine(
               {count, axisParam("Axis of rotation."), centerParam("A point on the axis."), angle}),
           [](CompileContext& c) {
             auto& b = c.b;
             const int n = static_cast<int>(c.real("count"));
             if (n == 1) return c.input(0);
             const double span = c.real("angle") * kPi / 180.0;
             const bool full = c.real("angle") == 360.0;
             const double step = full ? span / n : span / (n - 1);
             const Vec3 o = c.vec3("center");
             const Frame f = frameAlong(c.vec3("axis"));
             const Point3Slots q = localCoordinates(b, c.p, o, f);
             // Angles measured from the middle of the array, so that the branch cut of atan2
             // lies opposite it.
             const Vec3 m = inputCentre(c);
             const Vec3 dm = {m[0] - o[0], m[1] - o[1], m[2] - o[2]};
             const double u0 = dm[0] * f.u[0] + dm[1] * f.u[1] + dm[2] * f.u[2];
             const double v0 = dm[0] * f.v[0] + dm[1] * f.v[1] + dm[2] * f.v[2];
             const double first = (u0 == 0.0 && v0 == 0.0) ? 0.0 : std::atan2(v0, u0);
             const double middle = first + (full ? 0.0 : span / 2);
             const double cm = std::cos(middle), sm = std::sin(middle);
             const Slot ru = b.affine(q.x, q.y, q.y, cm, sm, 0, 0);
             const Slot rv = b.affine(q.x, q.y, q.y, -sm, cm, 0, 0);
             const Slot theta = b.emit(Op::Atan2, rv, ru);  // angle from the middle
             const Slot t =
                 b.affine(theta, theta, theta, 1.0 / step, 0, 0, full ? 0.0 : span / 2 / step);
             Slot v[3], j[3];
             for (int d = -1; d <= 1; ++d) {
               j[d + 1] = copyIndex(b, t, d, n, full);
               const Point3Slots turned =
                   turnedAboutW(b, q, b.affine(j[d + 1], j[d + 1], j[d + 1], -step, 0, 0, 0));
               v[d + 1] = c.input(0, fromLocalCoordinates(b, turned.x, turned.y, turned.z, o, f));
             }
             // two copies all round: the neighbours on both sides are the same copy
             return combineThree(c, v, j, full && n == 2);
           },
           [](const Node& n, const std::vector<Box3>& in) {
             return turnedAboutAxis(copyBox(n, in[0]), n.vec3("center"), n.vec3("axis"));
           }});
  }
}

}  // namespace frep

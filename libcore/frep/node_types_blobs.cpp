// Blobs: fields summed over a set of centres minus a threshold, HyperFun's soft solids. The
// sum makes nearby blobs melt into each other, which no set operation does. Each kernel
// decays with the distance r to its centre:
//   blobby        strength exp(-falloff r^2)                         (Blinn, hfBlobby)
//   soft_objects  1 - 22/9 t + 17/9 t^2 - 4/9 t^3 = (1 - t)^2 (1 - 4/9 t), t = min(r^2/R^2, 1)
//                 (Wyvill, hfSoft)
//   convolution   strength / (1 + sharpness^2 r^2)^2                  (Cauchy kernel, hfConvPoint)
//   metaballs     a (1 - 3 r^2/b^2) for r <= b/3, 3a/2 (1 - r/b)^2 for r <= b, 0 beyond
//                 (Nishimura, hfMetaBall)
// and convolution_segments integrates the Cauchy kernel along line segments in closed form
// (hfConvLine).
// HyperFun gives each centre its own strength; here one value serves all the centres of a
// node (sum several nodes' fields with `union` only where they do not meet).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <sstream>
#include <unordered_map>
#include <string>

#include "frep/instances.h"
#include "frep/node_helpers.h"
#include "frep/program.h"
#include "frep/program_builder.h"
#include "frep/registry.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"

namespace frep {

namespace {

using Kernel = std::function<Slot(ProgramBuilder&, Slot r2, const Node&)>;
// How far from its centre one kernel can still matter, given n centres and the threshold.
using Reach = std::function<double(const Node&, std::size_t n)>;
// The radius beyond which the centres are left out of the sum: where one kernel is exactly
// 0 (soft objects, metaballs), or where all the kernels beyond it together stay below
// kTailTolerance of the threshold (blobby's Gaussian); 0 where no radius does (the Cauchy
// kernel's tail: see below). Given the node and its number of centres.
using Support = std::function<double(const Node&, std::size_t n)>;

// The most the centres left out of a truncated (Gaussian) sum may add together, as a
// fraction of the threshold: far below what a mesh can show (the surface moves by about this
// fraction of the distance over which the field changes by the threshold).
constexpr double kTailTolerance = 1e-9;

// From this many centres on, a kernel with a support radius (exact or truncated) is summed
// through the instancer's spatial index (a point costs the centres within reach, not every
// centre); fewer are written out as instructions, which region specialisation can then
// shorten.
constexpr std::size_t kIndexedCentres = 16;

// The Cauchy kernel has no support radius and region specialisation cannot drop a term, so
// every point of the mesh sums every centre or segment: 100,000 of them took minutes before
// the first brick was done. The kernels with a reach take any number.
constexpr std::size_t kMostSummedTerms = 10000;

// With a reach, a point sums only the centres within it, but a pile sums them all: 85,000
// centres on one point made each evaluation cost 85,000 kernels. The most centres in the 27
// cells of the reach's size around any cell (an upper bound on those within reach of a point
// there) may be this many.
constexpr std::size_t kMostCentresNearby = 50000;

// "" or why the centres pile up more than a point may sum.
std::string tooCrowded(const std::vector<Vec3>& centres, double reach) {
  if (centres.size() <= kMostCentresNearby || !(reach > 0)) return "";
  std::unordered_map<std::uint64_t, std::size_t> cells;
  auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) {
    return (std::uint64_t(i) & 0x1FFFFF) << 42 | (std::uint64_t(j) & 0x1FFFFF) << 21 |
           (std::uint64_t(k) & 0x1FFFFF);
  };
  auto cellOf = [reach](double v) {  // (clamped: a centre at 1e300 has no int64 cell)
    return static_cast<std::int64_t>(std::clamp(std::floor(v / reach), -1e18, 1e18));
  };
  for (const Vec3& c : centres) ++cells[key(cellOf(c[0]), cellOf(c[1]), cellOf(c[2]))];
  std::size_t most = 0;
  for (const auto& entry : cells) {
    const std::int64_t i = std::int64_t(entry.first >> 42), j = std::int64_t(entry.first >> 21 & 0x1FFFFF),
                       k = std::int64_t(entry.first & 0x1FFFFF);
    std::size_t near = 0;
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
        for (int dk = -1; dk <= 1; ++dk) {
          auto it = cells.find(key(i + di, j + dj, k + dk));
          if (it != cells.end()) near += it->second;
        }
    most = std::max(most, near);
  }
  if (most <= kMostCentresNearby) return "";
  std::ostringstream os;
  os.precision(3);
  os << "parameter 'centers': up to " << most << " of its " << centres.size()
     << " centres lie near one point (within " << 2 * reach
     << ", the kernel's reach being " << reach << "); at most " << kMostCentresNearby
     << " may (each point of the mesh sums the centres within reach): spread them out or use "
        "fewer";
  return os.str();
}

// "" or why the node sums more terms than it may.
std::string tooManyTerms(const char* param, std::size_t terms, const char* what) {
  if (terms <= kMostSummedTerms) return "";
  return "parameter '" + std::string(param) + "' gives " + std::to_string(terms) + " " + what +
         "; at most " + std::to_string(kMostSummedTerms) +
         " are allowed (every point of the mesh sums the Cauchy kernel over all of them); "
         "soft_objects, metaballs and blobby sum only the centres within reach and take any "
         "number that is spread out";
}

// The sum of the kernels over the centres through an InstanceSet: the kernel, compiled once
// at the origin, is each copy. Its r^2 is the same (x - c)^2 sum the written-out form
// computes, and the centres it leaves out add exactly 0 there (soft objects, metaballs), so
// both forms give the same values; for a truncated kernel they differ by less than the
// tolerance.
Slot indexedSum(CompileContext& c, const std::vector<Vec3>& centres, const Kernel& kernel,
                double support) {
  ProgramBuilder kb;
  const Slot r2 = kb.add(kb.add(kb.sqr(kb.x()), kb.sqr(kb.y())), kb.sqr(kb.z()));
  auto one = std::make_shared<const Program>(kb.finish(kernel(kb, r2, c.node())));
  // A hair beyond the support: a centre whose kernel is not exactly 0 (or, truncated, is not
  // negligible) is always within reach.
  auto set = std::make_shared<const InstanceSet>(
      centres, std::vector<std::array<double, 9>>{}, std::move(one), support * (1 + 1e-9),
      InstanceSet::Combine::Sum, InstanceSet::Blend{});
  return c.b.external(std::move(set), c.p.x, c.p.y, c.p.z);
}

void addBlob(Registry& r, const char* id, const char* doc, const char* formula,
             std::vector<ParamTemplate> own, Kernel kernel, Reach reach,
             Support support = nullptr,
             std::function<std::string(const Node&)> check = nullptr) {
  std::vector<ParamTemplate> params = {
      pointsParam("centers", {{-0.4, 0, 0}, {0.4, 0, 0}}, 1, "length", "The blobs' centres.")};
  params.insert(params.end(), own.begin(), own.end());
  ParamTemplate threshold = realParam("threshold", 0.5, "", "Iso-level of the summed field.");
  range(threshold, 0.0, kInf, true);
  params.push_back(threshold);
  r.add({id, "primitive", doc, formula, 0, 0, params,
         [kernel, support](CompileContext& c) {
           auto& b = c.b;
           const std::vector<Vec3> centres = pointsOf(c.param("centers"));
           const double radius =
               support && centres.size() >= kIndexedCentres ? support(c.node(), centres.size()) : 0.0;
           if (radius > 0)
             return b.sub(indexedSum(c, centres, kernel, radius), b.constant(c.real("threshold")));
           Slot sum = 0;
           bool first = true;
           for (const Vec3& m : centres) {
             const Point3Slots d = shifted(b, c.p, m);
             const Slot r2 = b.add(b.add(b.sqr(d.x), b.sqr(d.y)), b.sqr(d.z));
             const Slot k = kernel(b, r2, c.node());
             sum = first ? k : b.add(sum, k);
             first = false;
           }
           return b.sub(sum, b.constant(c.real("threshold")));
         },
         [reach](const Node& n, const std::vector<Box3>&) {
           const std::vector<Vec3> pts = pointsOf(n.param("centers"));
           return pointsBounds(pts, reach(n, pts.size()));
         },
         [support, check](const Node& n) -> std::string {
           if (check) {
             std::string problem = check(n);
             if (!problem.empty()) return problem;
           }
           if (!support) return "";
           const std::vector<Vec3> centres = pointsOf(n.param("centers"));
           return tooCrowded(centres, support(n, centres.size()));
         }});
}

// strength * integral over the segment [a, a + l u] of 1 / (1 + s^2 r^2)^2 (Sherstyuk's
// closed form): with x the position along the segment and q^2 = 1 + s^2 (distance to its
// line)^2, x / (2q^2(q^2 + s^2x^2)) + (l-x) / (2q^2(q^2 + s^2(l-x)^2))
// + (atan(sx/q) + atan(s(l-x)/q)) / (2sq^3).
Slot segmentConvolution(ProgramBuilder& b, const Point3Slots& p, const Vec3& a, const Vec3& e,
                        double s, double strength) {
  const double l = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
  const Vec3 u = {e[0] / l, e[1] / l, e[2] / l};
  const Point3Slots d = shifted(b, p, a);
  const Slot x =
      b.affine(p.x, p.y, p.z, u[0], u[1], u[2], -(u[0] * a[0] + u[1] * a[1] + u[2] * a[2]));
  const Slot rest = b.affine(x, x, x, -1.0, 0, 0, l);  // l - x
  const Slot d2 = b.add(b.add(b.sqr(d.x), b.sqr(d.y)), b.sqr(d.z));
  const Slot across2 = b.max(b.sub(d2, b.sqr(x)), b.constant(0.0));  // rounding: never < 0
  const Slot q2 = b.affine(across2, across2, across2, s * s, 0, 0, 1.0);
  const Slot q = b.sqrt(q2);
  auto end = [&](Slot t) {  // t / (2 q^2 (q^2 + s^2 t^2))
    const Slot inner = b.add(q2, b.affine(b.sqr(t), t, t, s * s, 0, 0, 0));
    return b.div(t, b.affine(b.mul(q2, inner), t, t, 2.0, 0, 0, 0));
  };
  const Slot angles = b.add(b.emit(Op::Atan, b.div(b.affine(x, x, x, s, 0, 0, 0), q)),
                            b.emit(Op::Atan, b.div(b.affine(rest, rest, rest, s, 0, 0, 0), q)));
  const Slot middle = b.div(angles, b.affine(b.mul(q2, q), q, q, 2.0 * s, 0, 0, 0));
  const Slot sum = b.add(b.add(end(x), end(rest)), middle);
  return b.affine(sum, sum, sum, strength, 0, 0, 0);
}

// The segments of a skeleton: a polyline's consecutive points, or the points in pairs.
std::vector<std::pair<Vec3, Vec3>> skeletonSegments(const Node& n) {
  const std::vector<Vec3> pts = pointsOf(n.param("points"));
  const bool pairs = n.param("skeleton").text == "pairs";
  std::vector<std::pair<Vec3, Vec3>> out;
  for (std::size_t i = 0; i + 1 < pts.size(); i += pairs ? 2 : 1)
    out.push_back({pts[i], pts[i + 1]});
  return out;
}

}  // namespace

void registerBlobs(Registry& r) {
  addBlob(
      r, "blobby",
      "Blinn's blobby object: Gaussian bumps around the centres, summed. With 16 or more "
      "centres a point sums only the bumps within reach, the reach chosen so that all the "
      "others together add less than 1e-9 of the threshold.",
      "F = sum_i strength exp(-falloff |p - c_i|^2) - threshold",
      {positiveReal("strength", 1.0, "Height of each bump."),
       positiveReal("falloff", 8.0, "How fast a bump decays (per squared length).")},
      [](ProgramBuilder& b, Slot r2, const Node& n) {
        const Slot e = b.emit(Op::Exp, b.affine(r2, r2, r2, -n.real("falloff"), 0, 0, 0));
        return b.affine(e, e, e, n.real("strength"), 0, 0, 0);
      },
      [](const Node& n, std::size_t count) {
        // The sum exceeds the threshold only where some bump exceeds threshold / count.
        const double q = double(count) * n.real("strength") / n.real("threshold");
        return q > 1 ? std::sqrt(std::log(q) / n.real("falloff")) : 0.0;
      },
      [](const Node& n, std::size_t count) {
        // Beyond rho each of at most `count` bumps is below strength exp(-falloff rho^2),
        // so together they stay below kTailTolerance * threshold.
        const double q =
            double(count) * n.real("strength") / (kTailTolerance * n.real("threshold"));
        return q > 1 ? std::sqrt(std::log(q) / n.real("falloff")) : 0.0;
      });

  addBlob(
      r, "soft_objects",
      "Wyvill's soft objects: each centre's field falls smoothly to exactly 0 at `radius`, "
      "so distant blobs do not interact (and, with 16 or more centres, a point evaluates "
      "only the centres within `radius`: 100,000 centres are fine).",
      "t = min(|p - c_i|^2 / radius^2, 1);  F = sum_i (1 - 22/9 t + 17/9 t^2 - 4/9 t^3) - "
      "threshold",
      {positiveLength("radius", 0.6, "Reach of each centre's field.")},
      [](ProgramBuilder& b, Slot r2, const Node& n) {
        const double rr = n.real("radius");
        const Slot t = b.min(b.affine(r2, r2, r2, 1.0 / (rr * rr), 0, 0, 0), b.constant(1.0));
        // = (1 - t)^2 (1 - 4/9 t): exactly 0 from t = 1 on, with a zero slope there.
        const Slot rest = b.affine(t, t, t, -1.0, 0, 0, 1.0);
        return b.mul(b.sqr(rest), b.affine(t, t, t, -4.0 / 9.0, 0, 0, 1.0));
      },
      [](const Node& n, std::size_t) { return n.real("radius"); },
      [](const Node& n, std::size_t) { return n.real("radius"); });

  addBlob(
      r, "convolution",
      "A convolution surface of points with the Cauchy kernel (HyperFun hfConvPoint): "
      "smooth blobs whose size follows the sharpness. At most 10,000 centres: every point "
      "sums the kernel over all of them (soft_objects, metaballs and blobby take any number).",
      "F = sum_i strength / (1 + sharpness^2 |p - c_i|^2)^2 - threshold",
      {positiveReal("strength", 1.0, "Weight of each point."),
       positiveReal("sharpness", 3.0, "Kernel width parameter s (per length).")},
      [](ProgramBuilder& b, Slot r2, const Node& n) {
        const double s = n.real("sharpness");
        const Slot q = b.affine(r2, r2, r2, s * s, 0, 0, 1.0);
        return b.div(b.constant(n.real("strength")), b.sqr(q));
      },
      [](const Node& n, std::size_t count) {
        const double q = double(count) * n.real("strength") / n.real("threshold");
        const double s = n.real("sharpness");
        return q > 1 ? std::sqrt((std::sqrt(q) - 1) / (s * s)) : 0.0;
      },
      nullptr,
      [](const Node& n) {
        return tooManyTerms("centers", n.param("centers").numbers.size() / 3, "centres");
      });

  addBlob(
      r, "metaballs",
      "Nishimura's metaballs (HyperFun hfMetaBall): a piecewise quadratic bump that is "
      "exactly 0 from `radius` on, smooth (C1) everywhere, summed over the centres (with 16 "
      "or more, a point evaluates only the centres within `radius`).",
      "t = |p - c_i| / radius;  k = strength (1 - 3t^2) for t <= 1/3, 3/2 strength (1 - t)^2 "
      "for t <= 1, 0 beyond;  F = sum_i k_i - threshold",
      {positiveReal("strength", 1.0, "Height of each bump (b)."),
       positiveLength("radius", 1.0, "Reach of each centre's field (d).")},
      [](ProgramBuilder& b, Slot r2, const Node& n) {
        const double a = n.real("strength"), rr = n.real("radius");
        const Slot t = b.affine(b.sqrt(r2), r2, r2, 1.0 / rr, 0, 0, 0);
        const Slot inner = b.affine(b.sqr(t), t, t, -3.0 * a, 0, 0, a);
        const Slot rest = b.affine(b.min(t, b.constant(1.0)), t, t, -1.0, 0, 0, 1.0);
        const Slot outer = b.affine(b.sqr(rest), t, t, 1.5 * a, 0, 0, 0);
        return b.emit(Op::Select, b.affine(t, t, t, -1.0, 0, 0, 1.0 / 3.0), inner, outer);
      },
      [](const Node& n, std::size_t) { return n.real("radius"); },
      [](const Node& n, std::size_t) { return n.real("radius"); });

  {
    ParamTemplate points = pointsParam("points", {{-0.5, 0, 0}, {0.5, 0, 0}, {0.5, 0.6, 0}}, 2,
                                       "length", "The skeleton: a polyline, or pairs of points.");
    points.path = true;
    ParamTemplate threshold = realParam("threshold", 0.3, "", "Iso-level of the summed field.");
    range(threshold, 0.0, kInf, true);
    r.add({"convolution_segments",
           "primitive",
           "A convolution surface of line segments with the Cauchy kernel (HyperFun "
           "hfConvLine): the kernel integrated along the skeleton in closed form, so a "
           "polyline skeleton gives a smooth tube that swells where segments meet, with no "
           "bulge at the joints. At most 10,000 segments: every point sums them all.",
           "F = strength sum over the segments of the integral of 1 / (1 + sharpness^2 r^2)^2 "
           "along the segment (closed form with atan) - threshold",
           0,
           0,
           {points,
            choiceParam("skeleton", {"polyline", "pairs"},
                        "polyline: consecutive points are joined; pairs: each two points are "
                        "one segment (HyperFun's list of segments)."),
            positiveReal("strength", 1.0, "Weight of the skeleton (S)."),
            positiveReal("sharpness", 3.0, "Kernel width parameter s (per length)."), threshold},
           [](CompileContext& c) {
             auto& b = c.b;
             Slot sum = b.constant(0.0);
             for (const auto& seg : skeletonSegments(c.node())) {
               const Vec3 e = {seg.second[0] - seg.first[0], seg.second[1] - seg.first[1],
                               seg.second[2] - seg.first[2]};
               if (e[0] == 0 && e[1] == 0 && e[2] == 0) continue;  // no length, no weight
               sum = b.add(sum, segmentConvolution(b, c.p, seg.first, e, c.real("sharpness"),
                                                   c.real("strength")));
             }
             return b.sub(sum, b.constant(c.real("threshold")));
           },
           [](const Node& n, const std::vector<Box3>&) {
             // A segment's field is at most that of its infinite line, pi S / (2 s q^3), so
             // the sum reaches the threshold only where one segment gives threshold / count.
             const auto segs = skeletonSegments(n);
             const double s = n.real("sharpness");
             const double k =
                 double(segs.size()) * kPi * n.real("strength") / (2 * s * n.real("threshold"));
             const double pad = k > 1 ? std::sqrt((std::pow(k, 2.0 / 3.0) - 1) / (s * s)) : 0.0;
             return pointsBounds(pointsOf(n.param("points")), pad);
           },
           [](const Node& n) -> std::string {
             const std::size_t count = n.param("points").numbers.size() / 3;
             if (n.param("skeleton").text == "pairs" && count % 2)
               return "parameter 'points' has " + std::to_string(count) +
                      " points; with skeleton \"pairs\" it needs an even number";
             return tooManyTerms("points", skeletonSegments(n).size(), "segments");
           }});
  }
}

}  // namespace frep

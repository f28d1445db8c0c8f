// Blobs: fields summed over a set of centres minus a threshold, HyperFun's soft solids. The
// sum makes nearby blobs melt into each other, which no set operation does. Each kernel
// decays with the distance r to its centre:
//   blobby        strength exp(-falloff r^2)                         (Blinn, hfBlobby)
//   soft_objects  1 - 22/9 t + 17/9 t^2 - 4/9 t^3 = (1 - t)^2 (1 - 4/9 t), t = min(r^2/R^2, 1)
//                 (Wyvill, hfSoft)
//   convolution   strength / (1 + sharpness^2 r^2)^2                  (Cauchy kernel, hfConvPoint)
// HyperFun gives each centre its own strength; here one value serves all the centres of a
// node (sum several nodes' fields with `union` only where they do not meet).
#include <algorithm>
#include <cmath>
#include <functional>

#include "frep/node_helpers.h"
#include "frep/registry.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"

namespace frep {

namespace {

using Kernel = std::function<Slot(ProgramBuilder&, Slot r2, const Node&)>;
// How far from its centre one kernel can still matter, given n centres and the threshold.
using Reach = std::function<double(const Node&, std::size_t n)>;

void addBlob(Registry& r, const char* id, const char* doc, const char* formula,
             std::vector<ParamTemplate> own, Kernel kernel, Reach reach) {
  std::vector<ParamTemplate> params = {
      pointsParam("centers", {{-0.4, 0, 0}, {0.4, 0, 0}}, 1, "length", "The blobs' centres.")};
  params.insert(params.end(), own.begin(), own.end());
  ParamTemplate threshold = realParam("threshold", 0.5, "", "Iso-level of the summed field.");
  range(threshold, 0.0, kInf, true);
  params.push_back(threshold);
  r.add({id, "primitive", doc, formula, 0, 0, params,
         [kernel](CompileContext& c) {
           auto& b = c.b;
           Slot sum = 0;
           bool first = true;
           for (const Vec3& m : pointsOf(c.param("centers"))) {
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
         }});
}

}  // namespace

void registerBlobs(Registry& r) {
  addBlob(
      r, "blobby", "Blinn's blobby object: Gaussian bumps around the centres, summed.",
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
      });

  addBlob(
      r, "soft_objects",
      "Wyvill's soft objects: each centre's field falls smoothly to exactly 0 at `radius`, "
      "so distant blobs do not interact.",
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
      [](const Node& n, std::size_t) { return n.real("radius"); });

  addBlob(
      r, "convolution",
      "A convolution surface of points with the Cauchy kernel (HyperFun hfConvPoint): "
      "smooth blobs whose size follows the sharpness.",
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
      });
}

}  // namespace frep

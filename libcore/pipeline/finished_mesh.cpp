#include "pipeline/finished_mesh.h"

#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "base/errors.h"
#include "simplify/straighten_creases.h"

namespace frep {

FinishedMesh meshAndFinish(const Field& field, MeshingOptions options, const Finishing& finishing,
                           const std::function<bool(double)>& progress, bool keepMeshersMesh) {
  if (finishing.straightenCreases && !options.sharpFeatures)
    throw ModelError(
        "straightening creases needs sharp features (they find the creases); turn sharp "
        "features on or leave the creases as meshed");
  if (finishing.tolerance && !(*finishing.tolerance > 0.0 && std::isfinite(*finishing.tolerance))) {
    std::ostringstream os;
    os << "tolerance must be a distance > 0 (model units), got " << *finishing.tolerance;
    throw ModelError(os.str());
  }
  // (each step after meshing takes a few times the meshing's time)
  const double simplifyShare = finishing.tolerance ? 0.5 : 0.0;
  const double straightenShare = finishing.straightenCreases ? 0.5 * (1.0 - simplifyShare) : 0.0;
  const double meshShare = 1.0 - straightenShare - simplifyShare;
  auto part = [&progress](double from, double share) -> std::function<bool(double)> {
    if (!progress) return nullptr;
    return [&progress, from, share](double f) { return progress(from + share * f); };
  };
  if (finishing.straightenCreases || finishing.tolerance)
    options.bytesPerTriangle += kSimplifyBytesPerTriangle;
  options.progress = part(0.0, meshShare);

  FinishedMesh out;
  out.mesh = polygonize(field, options, &out.stats);
  // The mesher's mesh is kept when asked, and any other given up as it is replaced: no copies.
  bool changed = false;
  auto replace = [&](TriangleMesh next) {
    if (!changed && keepMeshersMesh) out.meshers = std::move(out.mesh);
    out.mesh = std::move(next);
    changed = true;
  };
  if (finishing.straightenCreases) {
    StraightenOptions st{options.bbox, options.resolution, part(meshShare, straightenShare)};
    replace(straightenCreases(out.mesh, field, st, &out.straighten));
    out.straightened = true;
  }
  if (finishing.tolerance) {
    SimplifyOptions so;
    so.bbox = options.bbox;
    so.cell = options.resolution;
    so.tolerance = *finishing.tolerance;
    so.sharpFeatures = options.sharpFeatures;
    so.progress = part(1.0 - simplifyShare, simplifyShare);
    replace(simplifyMesh(out.mesh, field, so, &out.simplify));
    out.simplified = true;
  }
  return out;
}

}  // namespace frep

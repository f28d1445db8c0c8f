#include "pipeline/finished_mesh.h"

#include <string>
#include <utility>
#include <vector>

#include "base/errors.h"
#include "base/mesh_invariants.h"
#include "base/phase_times.h"
#include "base/progress.h"
#include "simplify/straighten_creases.h"

namespace frep {

FinishedMesh meshAndFinish(const Field& field, MeshingOptions options,
                           const std::function<bool(double)>& progress, bool keepMeshersMesh) {
  const MeshSettings& settings = options.settings;
  settings.validate();
  // The bar: each step after meshing takes a few times the meshing's time: the
  // simplification half of it, the straightening half of the rest, meshing what remains.
  const double simplifyShare = settings.tolerance ? 0.5 : 0.0;
  const double straightenShare = settings.straightenCreases ? 0.5 * (1.0 - simplifyShare) : 0.0;
  const std::vector<Progress> phase = Progress(progress).phases(
      {1.0 - straightenShare - simplifyShare, straightenShare, simplifyShare});
  if (settings.straightenCreases || settings.tolerance)
    options.bytesPerTriangle += kSimplifyBytesPerTriangle;
  options.progress = phase[0].callback();

  FinishedMesh out;
  out.mesh = polygonize(field, options, &out.stats);
  // The mesher's mesh is kept when asked, and any other given up as it is replaced: no copies.
  bool changed = false;
  auto replace = [&](TriangleMesh next) {
    if (!changed && keepMeshersMesh) out.meshers = std::move(out.mesh);
    out.mesh = std::move(next);
    changed = true;
  };
  if (settings.straightenCreases) {
    const Phase timed("finish: straightened creases", PhaseKind::Parallel);
    StraightenOptions st{options.bbox, options.resolution, phase[1].callback()};
    replace(straightenCreases(out.mesh, field, st, &out.straighten));
    FREP_ASSERT_MESH(out.mesh, "the straightening");
    out.straightened = true;
  }
  if (settings.tolerance) {
    const Phase timed("finish: simplification", PhaseKind::Parallel);
    SimplifyOptions so;
    so.bbox = options.bbox;
    so.cell = options.resolution;
    so.tolerance = *settings.tolerance;
    so.sharpFeatures = settings.sharpFeatures;
    so.progress = phase[2].callback();
    replace(simplifyMesh(out.mesh, field, so, &out.simplify));
    FREP_ASSERT_MESH(out.mesh, "the simplification");
    out.simplified = true;
  }
  return out;
}

}  // namespace frep

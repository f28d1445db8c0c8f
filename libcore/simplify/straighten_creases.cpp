#include "simplify/straighten_creases.h"

namespace frep {

SimplifyOptions straightenOptions(const StraightenOptions& options) {
  SimplifyOptions o;
  o.bbox = options.bbox;
  o.cell = options.cell;
  o.tolerance = kStraightenToleranceCells * options.cell;
  o.maxEdge = kStraightenLongestEdgeCells * options.cell;
  o.sharpFeatures = true;
  o.creaseFlips = true;
  o.creaseCollapsesOnly = true;
  o.progress = options.progress;
  return o;
}

TriangleMesh straightenCreases(const TriangleMesh& mesh, const Field& field,
                               const StraightenOptions& options, SimplifyStats* stats) {
  return simplifyMesh(mesh, field, straightenOptions(options), stats);
}

}  // namespace frep

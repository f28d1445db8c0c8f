// The mesher's mesh and what follows it in every front end: the creases straightened
// (simplify/straighten_creases.h), then the mesh simplified within a tolerance
// (simplify/simplify.h). The export pipeline and frepcore's mesh() both come here, so they
// order the steps, share the progress bar and refuse bad options alike.
#pragma once

#include <functional>
#include <optional>

#include "frep/field.h"
#include "mesh/mesher.h"
#include "simplify/simplify.h"

namespace frep {

// Memory of the simplifier and the straightening, per triangle of the mesher's mesh (a
// quadric per vertex, the faces): added to MeshingOptions::bytesPerTriangle when either runs.
constexpr double kSimplifyBytesPerTriangle = 100.0;

struct FinishedMesh {
  TriangleMesh mesh;
  // The mesher's own mesh where a step changed it and keepMeshersMesh was asked (to fall
  // back on when the check refuses the finished one).
  TriangleMesh meshers;
  MeshingStats stats;
  bool straightened = false, simplified = false;
  SimplifyStats straighten, simplify;  // of the steps taken
};

// Meshes `field` with `options` (its progress and memory per triangle are set here), then
// straightens and simplifies as options.settings asks (straightenCreases, tolerance).
// progress(fraction) covers all of it: the simplification half the bar, the straightening
// half of the rest, meshing what remains; false cancels (throws Cancelled). Throws
// SettingError (MeshSettings::validate) before any work.
FinishedMesh meshAndFinish(const Field& field, MeshingOptions options,
                           const std::function<bool(double)>& progress, bool keepMeshersMesh);

}  // namespace frep

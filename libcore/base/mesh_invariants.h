// What the mesher and the steps after it promise of every mesh they hand on, checked at the
// end of each stage in debug builds (FREP_ASSERT_MESH; release builds compile it away, and
// the CGAL check judges every export anyway): every edge shared by exactly two triangles that
// run it in opposite directions (closed, 2-manifold at edges, consistently oriented), and no
// triangle with a repeated vertex.
#pragma once

#include <string>

#include "base/triangle_mesh.h"

namespace frep {

// Empty when `mesh` keeps the promise, else what breaks it first (a triangle and an edge).
std::string meshInvariantBroken(const TriangleMesh& mesh);

// Throws std::logic_error naming `stage` when the promise is broken (a bug).
void assertMeshInvariant(const TriangleMesh& mesh, const char* stage);

}  // namespace frep

#ifdef NDEBUG
#define FREP_ASSERT_MESH(mesh, stage) ((void)0)
#else
#define FREP_ASSERT_MESH(mesh, stage) ::frep::assertMeshInvariant((mesh), (stage))
#endif

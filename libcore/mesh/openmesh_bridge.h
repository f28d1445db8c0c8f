// Conversion between libcore's flat TriangleMesh and OpenMesh's halfedge structure, for the
// algorithms OpenMesh provides (halfedge queries, subdivision, decimation).
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "base/triangle_mesh.h"

namespace frep {

using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// Throws ModelError if OpenMesh rejects a face (a non-manifold configuration).
OMesh toOpenMesh(const TriangleMesh& mesh);
TriangleMesh fromOpenMesh(const OMesh& mesh);

}  // namespace frep

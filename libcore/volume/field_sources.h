// The loaders of the file-backed node types (frep/field_sources.h): `mesh_sdf` and `vdb_grid`.
// Every program that reads models calls registerVolumeSources() once at start-up (the CLI, the
// Python module, the tests).
#pragma once

#include <memory>
#include <string>

#include "base/triangle_mesh.h"
#include "frep/field.h"

namespace frep {

void registerVolumeSources();

enum class MeshFieldMethod { Exact, Grid };

// A closed mesh as a field (see the mesh_sdf node): exact distance, or an OpenVDB level set at
// `voxel` (0: 1/256 of the largest side). `where` names the mesh in messages.
std::shared_ptr<const Field> meshField(const TriangleMesh& mesh, MeshFieldMethod method,
                                       double voxel, const std::string& where);

}  // namespace frep

// Mesh files: binary and ASCII STL, OBJ, binary PLY, and FreeCAD's own binary mesh (.bms:
// points, facets and facet neighbours, which FreeCAD reads without rebuilding topology). Writers go through AtomicFile (no partial
// file on failure or cancel). Readers return the triangles exactly as stored; STL has no
// indices, so its vertices come unwelded (the checker welds identical coordinates).
#pragma once

#include <functional>
#include <string>

#include "base/triangle_mesh.h"

namespace frep {

enum class MeshFormat { StlBinary, StlAscii, Obj, Ply, FreecadBms };

const char* formatName(MeshFormat f);
// "stl", "stl-ascii", "obj", "ply", "bms"; throws ModelError naming the allowed values.
MeshFormat parseFormat(const std::string& name);
// From the file extension (.stl -> binary STL); throws FileError for an unknown extension.
MeshFormat formatFromPath(const std::string& path);

// Called with the fraction written; return false to cancel (throws Cancelled, no file).
using WriteProgress = std::function<bool(double)>;

void writeMesh(const TriangleMesh& mesh, const std::string& path, MeshFormat format,
               const WriteProgress& progress = {});

// Reads STL (binary or ASCII, detected from content), OBJ or PLY (ASCII or binary little
// endian). Polygons are fan-triangulated. Throws FileError with the file name and the problem.
TriangleMesh readMesh(const std::string& path);

}  // namespace frep

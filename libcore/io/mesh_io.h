// Mesh files: binary and ASCII STL, OBJ, binary PLY, OFF (read only), 3MF (one object;
// io/mesh_3mf.h for several), and FreeCAD's own binary mesh (.bms: points, facets and facet
// neighbours, which FreeCAD reads without rebuilding topology). Writers go through AtomicFile (no
// partial file on failure or cancel). Readers return the triangles exactly as stored; STL has no
// indices, so its vertices come unwelded (the checker welds identical coordinates).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "base/atomic_file.h"
#include "base/progress.h"
#include "base/triangle_mesh.h"

namespace frep {

enum class MeshFormat { StlBinary, StlAscii, Obj, Ply, FreecadBms, ThreeMf };

const char* formatName(MeshFormat f);
// "stl", "stl-ascii", "obj", "ply", "bms", "3mf"; throws ModelError naming the allowed values.
MeshFormat parseFormat(const std::string& name);
// From the file name's extension (.stl -> binary STL); throws FileError for an unknown one,
// naming the types `allowed` lists.
MeshFormat formatFromPath(const std::string& path,
                          const char* allowed = "written: .stl, .obj, .ply, .bms, .3mf");

// Called with the fraction written; return false to cancel (throws Cancelled, no file).
using WriteProgress = std::function<bool(double)>;

void writeMesh(const TriangleMesh& mesh, const std::string& path, MeshFormat format,
               const WriteProgress& progress = {});
// The same, left under its temporary name: commit() renames it into place, destroying it
// removes it. The export writes while its check runs and renames only what the check
// accepts. A 3MF gets one object named after the file (io/mesh_3mf.h writes several).
std::unique_ptr<AtomicFile> writeMeshUncommitted(const TriangleMesh& mesh, const std::string& path,
                                                 MeshFormat format,
                                                 const WriteProgress& progress = {});

// Reads STL (binary or ASCII, detected from content), OBJ, PLY (ASCII or binary little
// endian), OFF (text) or 3MF (every build item, merged: io/mesh_3mf.h reads them one by one),
// chosen by the file name's extension. Polygons are fan-triangulated. Numbers are read
// strictly (a word that is not wholly a number is an error, not a 0 or a truncated index).
// Throws FileError with the file name and the problem, also for a file without faces, and
// Cancelled when `cancel` asks (polled every million triangles or lines).
TriangleMesh readMesh(const std::string& path, const Progress& cancel = {});

}  // namespace frep

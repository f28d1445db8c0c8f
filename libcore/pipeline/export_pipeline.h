// The one export pipeline: box policy -> mesh -> check -> write, with progress and cancel
// across all of it. The CLI (JSON and, through the workbench, FCStd inputs), frepcore and the
// workbench all come here, so they choose the same box, mesh the same way and refuse the
// same meshes.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "base/vec.h"
#include "check/mesh_check.h"
#include "frep/bounds.h"
#include "frep/field.h"
#include "io/mesh_3mf.h"
#include "io/mesh_io.h"
#include "mesh/mesher.h"
#include "pipeline/accuracy.h"
#include "pipeline/finished_mesh.h"
#include "simplify/simplify.h"
#include "simplify/straighten_creases.h"

namespace frep {

// Grid cells along the longest side of the solid's box when no cell size is given.
constexpr int kDefaultCells = 128;
// The automatic box is the solid's own box grown by this many cells (and 1/1000 of its
// size), so the surface never touches the meshing box.
constexpr double kPaddingCells = 1.5;
// Memory per triangle of meshing, and what the check adds to it (measured:
// docs/performance.md, "Memory"; at 512 cells the whole export peaks at 50
// to 83 bytes a triangle in frepcad, 61 to 79 in the Python module, on the reference
// models; meshing alone at up to 50).
constexpr double kMesherBytesPerTriangle = 60.0;
constexpr double kCheckBytesPerTriangle = 40.0;
// Cells along the longest side that `cells` may ask for.
constexpr int kMaxCells = 1 << 16;

struct BoxRequest {
  std::optional<Box3> bbox;          // given: meshed as is
  std::optional<double> resolution;  // cell size; wins over cells
  std::optional<int> cells;          // cells along the longest side (kDefaultCells)
  double paddingCells = kPaddingCells;
};

struct MeshingBox {
  Box3 box;
  double resolution = 0.0;
};

// The box policy. Without a bbox the solid's box comes from `bounds` (findBounds); an empty or
// unbounded solid is a ModelError saying what to do. Bad requests (resolution <= 0, cells out
// of range, an inverted box) are ModelErrors naming the parameter.
MeshingBox chooseBox(const SolidBounds& bounds, const BoxRequest& request);
// The same, finding the bounds of `field` itself when they are needed; `known` is a box the
// solid is known to lie in (structuralBounds of its tree).
MeshingBox chooseBox(const Field& field, const Box3& known, const BoxRequest& request);

enum class ExportStage { Bounds, Mesh, Check, Write };
const char* stageName(ExportStage s);

struct ExportRequest {
  BoxRequest box;
  Box3 known = BoundsOptions().known;  // structural bounds of the solid, when known
  std::optional<MeshFormat> format;    // default: from the output's extension
  ThreeMfOptions threeMf;              // a 3MF's unit and metadata
  std::string objectName;              // a 3MF object's name (default: the file's stem)
  bool check = true;                   // judge the mesh with CGAL before writing
  bool force = false;                  // write a mesh the check refused
  bool normals = true;                 // vertex normals from the gradient (OBJ and PLY keep them)
  MeshSettings mesh;  // the mesher's and the finishing's options (mesh/mesh_settings.h)
  // Measure the written mesh against the exact surface (pipeline/accuracy.h): distances
  // both ways, volume, crease length. Costs a mesh at half the cell size.
  bool stats = false;
  // Memory the export may take; default: what the system has available now. A mesh
  // estimated to need more is refused before it is made (MeshingOptions::memoryBudget).
  std::optional<std::size_t> memoryBudget;
  // (stage, fraction of that stage done); false cancels: throws Cancelled, nothing written.
  // Called from the calling thread or worker threads, one call at a time.
  std::function<bool(ExportStage, double)> progress;
};

struct ExportResult {
  MeshingBox box;
  MeshingStats stats;
  CheckReport report;  // empty when the check was not asked for
  bool checked = false;
  bool written = false;  // false: the check refused the mesh (and force was not given)
  std::size_t triangles = 0;
  bool simplified = false;
  SimplifyStats simplify;  // when simplified (its seconds are part of meshing's)
  bool straightened = false;
  SimplifyStats straighten;  // when creases were straightened (seconds: as simplify's)
  // The simplified or straightened mesh failed the check (a bug: please report it) and the
  // mesher's own, printable, was written instead.
  bool simplificationRefused = false;
  std::optional<AccuracyReport> accuracy;  // when stats were asked for
  // exportPieces (brick jobs): the check judged the pieces one by one and the zone where
  // they meet (check/partitioned_check.h), never holding the whole mesh
  bool checkedInParts = false;
  double seconds[4] = {0, 0, 0, 0};  // per ExportStage
};

// Meshes `field`, checks and writes `path` atomically (nothing is left on failure or cancel;
// an existing file is replaced only by a complete new one). `name` names the solid in
// messages. Throws ModelError, FileError, Cancelled.
ExportResult exportField(const Field& field, const ExportRequest& request, const std::string& path,
                         const std::string& name);

// Several meshes as the objects of one 3MF: the package is made in memory and read back
// (io/mesh_3mf.h), every object as the file holds it is checked, and the file is written
// atomically only when all pass (or `force`). `progress(fraction)`: false cancels (Cancelled).
struct ThreeMfExportResult {
  std::vector<CheckReport> reports;  // one per object, in order
  bool written = false;
  bool printable() const {
    for (const CheckReport& r : reports)
      if (!r.printable()) return false;
    return !reports.empty();
  }
};
ThreeMfExportResult export3mf(const std::vector<NamedMesh>& objects, const ThreeMfOptions& options,
                              const std::string& path, bool force,
                              const std::function<bool(double)>& progress = nullptr);

}  // namespace frep

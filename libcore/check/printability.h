// What a printer makes of a mesh beyond the check's verdict: wall thickness (a shape diameter
// of each triangle: rays cast into the solid within a cone around the inward normal, as CGAL's
// shape diameter function does; the deepest first hit, measured along the normal, so that a
// flat wall measures exactly and a triangle beside a convex edge is not made thin by rays
// that leave through the side),
// regions thinner than a minimum, the overhang area for a build direction, height,
// and mass for a material (volume, area and bounding box are the check's).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "base/triangle_mesh.h"
#include "base/vec.h"
#include "check/mesh_check.h"

namespace frep {

struct Material {
  const char* name;
  double density;  // g/cm^3
};
// pla, petg, abs, asa, nylon, tpu, resin, 316l, ti64, alsi10mg.
const std::vector<Material>& materials();
// The material's density; throws ModelError naming the known materials.
double materialDensity(const std::string& name);

struct PrintabilityOptions {
  Vec3 up{0, 0, 1};               // build direction (normalised here)
  double overhangDeg = 45.0;      // a downward face steeper than this from vertical needs support
  std::optional<double> minWall;  // report faces thinner than this
  double density = 0.0;           // g/cm^3 (model units taken as mm); 0: no mass
  double coneDeg = 20.0;          // half-angle of the cone of rays
  int rays = 9;                   // rays per triangle
  // Measure the walls. Off for a mesh the check refuses: an open or crossing surface has no
  // walls, and rays through a soup of large crossing triangles meet every one of them.
  bool thickness = true;
};

struct PrintabilityReport {
  // Per triangle of the mesh (in its order): the wall thickness there, or -1 where no ray met
  // the surface again (an open mesh).
  std::vector<float> thickness;
  double minWall = -1;            // the thinnest triangle's thickness; -1: none measured
  Vec3 minWallAt{0, 0, 0};        // that triangle's centre
  std::size_t thinTriangles = 0;  // thinner than options.minWall
  double thinArea = 0.0;
  double overhangArea = 0.0;  // downward faces past the angle, not lying on the build plate
  std::size_t overhangTriangles = 0;
  double volume = 0.0;  // signed, for the mass (the check's report gives it, with the area)
  double height = 0.0;  // along the build direction
  double mass = 0.0;    // grams, when a density was given
  // Closed voids inside the solid (components of a printable mesh whose normals point in):
  // resin and powder printers cannot empty them. Counted on printable meshes only
  // (PrintabilityOptions::thickness); -1: not counted.
  long long cavities = -1;
  double cavityVolume = 0.0;
  // Each cavity, largest first: its volume and where a drain hole along the build direction
  // empties it: a point of its floor (its wall near its lowest point), well inside the floor
  // (infill's drain_holes takes such points).
  struct Cavity {
    double volume = 0.0;
    Vec3 drainAt{0, 0, 0};
  };
  std::vector<Cavity> cavityList;
  // Per triangle of the mesh: the index in cavityList of the cavity whose wall it is, or -1
  // (empty when cavities were not counted).
  std::vector<std::int32_t> cavityOf;
};

// Throws ModelError for bad options (a zero build direction, angles out of range, rays < 1).
PrintabilityReport measurePrintability(const TriangleMesh& mesh,
                                       const PrintabilityOptions& options);

// Adds to the check's reasons what makes the part unprintable for the printer: walls thinner
// than options.minWall.
void addPrintabilityReasons(CheckReport& check, const PrintabilityReport& r,
                            const PrintabilityOptions& options);

// The report for people (after the check's own text), and the check's JSON report with a
// "print" object added (check_report_format.cpp).
std::string printabilityToText(const PrintabilityReport& r, const PrintabilityOptions& options);
std::string printabilityToJson(const CheckReport& check, const PrintabilityReport& r,
                               const PrintabilityOptions& options, const std::string& name);

}  // namespace frep

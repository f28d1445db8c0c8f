// Strut (beam) lattices: the struts of a periodic unit cell (simple cubic, BCC, FCC, octet,
// Kelvin, diamond) as capsules of one radius, or of a radius a field gives point by point
// (graded), with optional spheres at the nodes. The field is radius - the exact distance to
// the struts' centre lines, so outside the struts the signed distance to their union.
// A point is folded into one small domain and meets only the struts there (strut_cells.h):
// no list of every strut, so the field's program is the same size for any number of cells.
#include <algorithm>
#include <string>

#include "frep/node_helpers.h"
#include "frep/registry.h"
#include "frep/strut_cells.h"
#include "frep/strut_field.h"
#include "frep/tree.h"

namespace frep {

namespace {

std::vector<std::string> cellIds() {
  std::vector<std::string> ids;
  for (const UnitCell& c : unitCells()) ids.push_back(c.id);
  return ids;
}

std::string cellDocs() {
  std::string text;
  for (const UnitCell& c : unitCells()) text += (text.empty() ? "" : "; ") + c.id + ": " + c.doc;
  return text;
}

// The point's coordinate along an axis folded by the cell's period into [0, size), or into
// [-size / 2, size / 2) (centred), and by the axis' mirrors into [0, size / 2] (mirror).
Slot fold(ProgramBuilder& b, Slot p, double size, double origin, bool centred, bool mirror) {
  const double shift = centred ? 0.5 : 0.0;
  const Slot k = b.emit(Op::Floor, b.affine(p, p, p, 1.0 / size, 0.0, 0.0, shift - origin / size));
  const Slot w = b.affine(p, k, k, 1.0, -size, 0.0, -origin);  // p - origin - size k
  if (!mirror) return w;
  const Slot centre = b.abs(b.affine(w, w, w, 1.0, 0.0, 0.0, -0.5 * size));
  return b.affine(centre, centre, centre, -1.0, 0.0, 0.0, 0.5 * size);
}

// A point of [-c/2, c/2]^3 folded into x >= y >= |z| by the mirrors x = +-y, y = +-z, x = +-z:
// its coordinates' sizes in order, the smallest negative where an odd number were.
Point3Slots foldTetrahedral(ProgramBuilder& b, const Point3Slots& w) {
  const Slot x = b.abs(w.x), y = b.abs(w.y), z = b.abs(w.z);
  const Slot largest = b.max(b.max(x, y), z), smallest = b.min(b.min(x, y), z);
  const Slot middle = b.max(b.min(x, y), b.min(b.max(x, y), z));
  const Slot parity = b.mul(b.mul(w.x, w.y), w.z);
  return {largest, middle, b.emit(Op::Select, parity, smallest, b.emit(Op::Neg, smallest))};
}

Slot strutLattice(CompileContext& c) {
  const Slot radius = c.inputCount() ? c.input(0) : c.b.constant(c.real("radius"));
  return strutLatticeField(c.b, c.p, unitCell(c.param("cell_type").text), c.vec3("cell"),
                           c.vec3("origin"), radius, c.real("node_radius"));
}

// A cell folded by translation only looks at the struts within the covering radius of its
// longest side round the cell: along a much shorter side that is many cells (and many struts).
constexpr double kMostUnevenCell = 4.0;

std::string checkStrutLattice(const Node& node) {
  if (unitCell(node.param("cell_type").text).mirrorSymmetric) return "";
  const Vec3 size = node.vec3("cell");
  const double ratio =
      std::max({size[0], size[1], size[2]}) / std::min({size[0], size[1], size[2]});
  if (ratio <= kMostUnevenCell) return "";
  return "parameter 'cell' = (" + std::to_string(size[0]) + ", " + std::to_string(size[1]) + ", " +
         std::to_string(size[2]) + ") is " + std::to_string(ratio) +
         " times longer along one axis than another; a " + node.param("cell_type").text +
         " cell allows at most " + std::to_string(int(kMostUnevenCell)) + " times";
}

}  // namespace

Slot strutLatticeField(ProgramBuilder& b, const Point3Slots& p, const UnitCell& cell,
                       const Vec3& size, const Vec3& origin, Slot radius, double nodeRadius) {
  const FoldedCell folded = foldedCell(cell, size);
  using Fold = FoldedCell::Fold;
  const bool centred = folded.fold == Fold::Tetrahedral, mirror = folded.fold == Fold::Mirror;
  Point3Slots q = {fold(b, p.x, size[0], origin[0], centred, mirror),
                   fold(b, p.y, size[1], origin[1], centred, mirror),
                   fold(b, p.z, size[2], origin[2], centred, mirror)};
  if (folded.fold == Fold::Tetrahedral) q = foldTetrahedral(b, q);
  Slot nearest = 0;
  for (std::size_t i = 0; i < folded.pieces.size(); ++i) {
    const StrutPiece& s = folded.pieces[i];
    const Slot d = segmentDistance(b, q, s.a, vsub(s.b, s.a));
    nearest = i == 0 ? d : b.min(nearest, d);
  }
  Slot field = b.sub(radius, nearest);
  if (nodeRadius > 0.0 && !folded.nodes.empty()) {
    Slot node = 0;
    for (std::size_t i = 0; i < folded.nodes.size(); ++i) {
      const Slot d = segmentDistance(b, q, folded.nodes[i], {0, 0, 0});
      node = i == 0 ? d : b.min(node, d);
    }
    field = b.max(field, b.sub(b.constant(nodeRadius), node));
  }
  return field;
}

void registerStrutLattices(Registry& r) {
  ParamTemplate size = vec3Param("cell", {1, 1, 1}, "length",
                                 "The unit cell's size along x, y and z (the lattice's period).");
  range(size, 0.0, kInf, true);
  ParamTemplate nodeRadius =
      realParam("node_radius", 0.0, "length",
                "Radius of a sphere at every node where struts meet (0: none; a sphere larger "
                "than the struts rounds and strengthens the joints).");
  range(nodeRadius, 0.0, kInf);
  r.add({"strut_lattice",
         "microstructure",
         "A strut (beam) lattice: the struts of a unit cell repeated along x, y and z, each a "
         "capsule of the given radius. Unit cells: " +
             cellDocs() +
             ". Optional input: a field whose value replaces `radius` point by point (graded "
             "struts, e.g. thicker towards a load). Unbounded: intersect it with a part, or use "
             "it as an infill's lattice.",
         "q = p - origin folded into the cell by its period, and by the cell's mirrors into "
         "[0, cell / 2]^3 (diamond in a cube cell: into x >= y >= |z| round a node);  F = radius - "
         "min over the struts s near q of "
         "dist(q, s);  with node spheres F = max(F, node_radius - min over the nodes n of "
         "|q - n|)  (radius = input's value when given)",
         0,
         1,
         {choiceParam("cell_type", cellIds(), "The unit cell."), size,
          positiveLength("radius", 0.1, "Radius of every strut."), nodeRadius,
          vec3Param("origin", {0, 0, 0}, "length", "Where a cell starts (shifts the lattice).")},
         strutLattice,
         nullptr,
         checkStrutLattice});
}

}  // namespace frep

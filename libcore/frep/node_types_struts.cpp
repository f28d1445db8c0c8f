// Strut (beam) lattices: the struts of a periodic unit cell (simple cubic, BCC, FCC, octet,
// Kelvin, diamond) as capsules of one radius, or of a radius a field gives point by point
// (graded), with optional spheres at the nodes. The field is radius - the exact distance to
// the struts' centre lines, so outside the struts the signed distance to their union.
// A point is folded into one small domain and meets only the struts there (strut_cells.h):
// no list of every strut, so the field's program is the same size for any number of cells.
#include <algorithm>
#include <cmath>
#include <string>

#include "base/errors.h"
#include "frep/conformal_chords.h"
#include "frep/field_sources.h"
#include "frep/node_helpers.h"
#include "frep/periodic_segments.h"
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

// Cells that follow a cylinder: the point's distance from the axis, its arc round the axis
// (at the radius where `around` cells make a turn) and its height along the axis are the
// lattice's x, y and z, so the struts curve with the cylinder and a turn holds whole cells
// (the fold along y meets itself across the angle's cut).
Point3Slots cylinderCoordinates(CompileContext& c, double arcPerRadian) {
  ProgramBuilder& b = c.b;
  const Point3Slots q = localCoordinates(b, c.p, c.vec3("origin"), frameAlong(c.vec3("axis")));
  const Slot across = b.sqrt(b.add(b.sqr(q.x), b.sqr(q.y)));
  const Slot angle = b.emit(Op::Atan2, q.y, q.x);
  return {across, b.affine(angle, angle, angle, arcPerRadian, 0.0, 0.0, 0.0), q.z};
}

// Cells that follow a sphere round `origin`: the point's distance from the centre, its arc
// round the axis (longitude) and its arc from the axis' pole (latitude), each arc at the radius
// where `around` cells make a turn, are the lattice's x, y and z. A turn of longitude holds
// whole cells; the cells narrow towards the poles, as a globe's do.
Point3Slots sphereCoordinates(CompileContext& c, double arcPerRadianY, double arcPerRadianZ) {
  ProgramBuilder& b = c.b;
  const Point3Slots q = localCoordinates(b, c.p, c.vec3("origin"), frameAlong(c.vec3("axis")));
  const Slot across = b.sqrt(b.add(b.sqr(q.x), b.sqr(q.y)));
  const Slot distance = b.sqrt(b.add(b.add(b.sqr(q.x), b.sqr(q.y)), b.sqr(q.z)));
  const Slot longitude = b.emit(Op::Atan2, q.y, q.x);
  const Slot fromPole = b.emit(Op::Atan2, across, q.z);
  return {distance, b.affine(longitude, longitude, longitude, arcPerRadianY, 0.0, 0.0, 0.0),
          b.affine(fromPole, fromPole, fromPole, arcPerRadianZ, 0.0, 0.0, 0.0)};
}

// Straight struts of conformal cells: radius - the distance to the chords (exact within half
// the cell's shortest side, the blend, and twice the radius and node radius; no surface lies
// farther out), and the node spheres at the nodes' images.
Slot straightConformal(CompileContext& c, const UnitCell& cell, Slot radius) {
  ConformalCells cells;
  cells.cell = &cell;
  cells.size = c.vec3("cell");
  cells.origin = c.vec3("origin");
  cells.axis = c.vec3("axis");
  cells.sphere = c.param("conform").text == "sphere";
  cells.around = int(c.real("around"));
  cells.blend = c.real("blend");
  const double nodeRadius = c.real("node_radius");
  const double exact = conformalExactWithin(cells.size, cells.blend, c.real("radius"), nodeRadius);
  ProgramBuilder& b = c.b;
  const auto chords = std::make_shared<const ConformalChordsField>(cells, exact, false);
  Slot field = b.sub(radius, b.external(chords, c.p.x, c.p.y, c.p.z));
  if (nodeRadius > 0.0 && !cell.nodes.empty()) {
    const auto nodes = std::make_shared<const ConformalChordsField>(cells, exact, true);
    field = b.max(field, b.sub(b.constant(nodeRadius), b.external(nodes, c.p.x, c.p.y, c.p.z)));
  }
  return field;
}

Slot strutLattice(CompileContext& c) {
  const Slot radius = c.inputCount() ? c.input(0) : c.b.constant(c.real("radius"));
  const UnitCell& cell = unitCell(c.param("cell_type").text);
  const Vec3 size = c.vec3("cell");
  const std::string& conform = c.param("conform").text;
  if ((conform == "cylinder" || conform == "sphere") && c.param("struts").text == "straight")
    return straightConformal(c, cell, radius);
  if (conform == "cylinder" || conform == "sphere") {
    const double perTurn = c.real("around") / (2.0 * kPi);
    const Point3Slots q = conform == "cylinder"
                              ? cylinderCoordinates(c, perTurn * size[1])
                              : sphereCoordinates(c, perTurn * size[1], perTurn * size[2]);
    return strutLatticeField(c.b, q, cell, size, {0, 0, 0}, radius, c.real("node_radius"),
                             c.real("blend"));
  }
  return strutLatticeField(c.b, c.p, cell, size, c.vec3("origin"), radius, c.real("node_radius"),
                           c.real("blend"));
}

// A cell folded by translation only looks at the struts within the covering radius of its
// longest side round the cell: along a much shorter side that is many cells (and many struts).
constexpr double kMostUnevenCell = 4.0;

std::string checkCellRatio(const Node& node, const std::string& what) {
  const Vec3 size = node.vec3("cell");
  const double ratio =
      std::max({size[0], size[1], size[2]}) / std::min({size[0], size[1], size[2]});
  if (ratio <= kMostUnevenCell) return "";
  return "parameter 'cell' = (" + numberText(size[0]) + ", " + numberText(size[1]) + ", " +
         numberText(size[2]) + ") is " + numberText(ratio) +
         " times longer along one axis than another; " + what + " allows at most " +
         std::to_string(int(kMostUnevenCell)) + " times";
}

// A blend reaches past the struts within it of the nearest: beyond half a cell it would
// reach across cells (and make every strut of many cells count).
std::string checkBlend(const Node& node) {
  const Vec3 size = node.vec3("cell");
  const double most = 0.5 * std::min({size[0], size[1], size[2]}), blend = node.real("blend");
  if (blend <= most) return "";
  return "parameter 'blend' = " + numberText(blend) + " is more than half the cell's " +
         "shortest side (" + numberText(most) + ")";
}

// Straight conformal struts gather a layer's struts (a whole turn of them next to the axis).
std::string checkStraightConformal(const Node& node) {
  const std::string& conform = node.param("conform").text;
  if (conform == "none" || node.param("struts").text != "straight") return "";
  ConformalCells cells;
  cells.cell = &unitCell(node.param("cell_type").text);
  cells.size = node.vec3("cell");
  cells.sphere = conform == "sphere";
  cells.around = int(node.real("around"));
  const double gathered = largestLayerStruts(
      cells, conformalExactWithin(cells.size, node.real("blend"), node.real("radius"),
                                  node.real("node_radius")));
  if (gathered <= kMostLayerStruts) return "";
  return "parameter 'struts' = 'straight' with this 'cell' and 'around' gathers about " +
         numberText(std::round(gathered)) + " struts for a turn of cells next to the " +
         (cells.sphere ? "centre" : "axis") + "; at most " + numberText(kMostLayerStruts) +
         " (fewer cells around, a cell less uneven, or a thinner radius)";
}

std::string checkStrutLattice(const Node& node) {
  if (std::string blend = checkBlend(node); !blend.empty()) return blend;
  if (std::string straight = checkStraightConformal(node); !straight.empty()) return straight;
  // (a blend needs every strut near the cell: the cell is then folded by translation only)
  if (unitCell(node.param("cell_type").text).mirrorSymmetric && node.real("blend") == 0.0)
    return "";
  return checkCellRatio(node, "a " + node.param("cell_type").text + " cell");
}

Slot voronoiFoam(CompileContext& c) {
  const Slot radius = c.inputCount() ? c.input(0) : c.b.constant(c.real("radius"));
  return voronoiFoamField(c.b, c.p, c.node(), radius, c.real("node_radius"));
}

std::string checkVoronoiFoam(const Node& node) {
  if (std::string blend = checkBlend(node); !blend.empty()) return blend;
  const std::string uneven = checkCellRatio(node, "a foam's cell");
  if (!uneven.empty()) return uneven;
  const std::array<int, 3> cells = foamCellsPerPeriod(node.vec3("cell"), int(node.real("tile")));
  const long seeds = long(cells[0]) * cells[1] * cells[2];
  if (seeds <= kMostFoamSeeds) return "";
  return "parameter 'tile' = " + std::to_string(int(node.real("tile"))) +
         " with this 'cell' makes " + std::to_string(cells[0]) + " x " + std::to_string(cells[1]) +
         " x " + std::to_string(cells[2]) + " = " + std::to_string(seeds) +
         " seeds a period; at most " + std::to_string(kMostFoamSeeds) +
         " (a smaller tile or a more even cell)";
}

}  // namespace

Slot strutLatticeField(ProgramBuilder& b, const Point3Slots& p, const UnitCell& cell,
                       const Vec3& size, const Vec3& origin, Slot radius, double nodeRadius,
                       double blend) {
  const FoldedCell folded = foldedCell(cell, size, blend);
  using Fold = FoldedCell::Fold;
  const bool centred = folded.fold == Fold::Tetrahedral, mirror = folded.fold == Fold::Mirror;
  Point3Slots q = {fold(b, p.x, size[0], origin[0], centred, mirror),
                   fold(b, p.y, size[1], origin[1], centred, mirror),
                   fold(b, p.z, size[2], origin[2], centred, mirror)};
  if (folded.fold == Fold::Tetrahedral) q = foldTetrahedral(b, q);
  // Without a blend, the nearest strut's distance is the square root of the least squared
  // distance (the same bits as the least of the roots: sqrt is monotone and correctly
  // rounded), one root a point instead of one a strut.
  Slot nearest = 0;
  std::vector<Slot> distances;
  for (std::size_t i = 0; i < folded.pieces.size(); ++i) {
    const StrutPiece& s = folded.pieces[i];
    Slot d = segmentDistanceSquared(b, q, s.a, vsub(s.b, s.a));
    if (blend > 0.0) d = b.sqrt(d);
    nearest = i == 0 ? d : b.min(nearest, d);
    distances.push_back(d);
  }
  if (blend == 0.0) nearest = b.sqrt(nearest);
  if (blend > 0.0) {
    // The smooth minimum of every strut's distance (PeriodicSegmentsField has the formula):
    // symmetric in the struts, so the same on both sides of a cell's face whatever order the
    // folded pieces come in.
    Slot sum = 0;
    for (std::size_t i = 0; i < distances.size(); ++i) {
      const Slot t =
          b.max(b.affine(distances[i], nearest, nearest, -1.0 / blend, 1.0 / blend, 0.0, 1.0),
                b.constant(0.0));
      sum = i == 0 ? b.sqr(t) : b.add(sum, b.sqr(t));
    }
    nearest = b.add(b.affine(nearest, nearest, nearest, 1.0, 0.0, 0.0, -0.5 * blend),
                    b.emit(Op::Div, b.constant(0.5 * blend), sum));
  }
  Slot field = b.sub(radius, nearest);
  if (nodeRadius > 0.0 && !folded.nodes.empty()) {
    Slot node = 0;
    for (std::size_t i = 0; i < folded.nodes.size(); ++i) {
      const Slot d = segmentDistanceSquared(b, q, folded.nodes[i], {0, 0, 0});
      node = i == 0 ? d : b.min(node, d);
    }
    field = b.max(field, b.sub(b.constant(nodeRadius), b.sqrt(node)));
  }
  return field;
}

// The foam's edges and nodes come from its loader (volume/voronoi_foam.h: CGAL's Delaunay
// triangulation), as one periodic network field each.
Slot voronoiFoamField(ProgramBuilder& b, const Point3Slots& p, const Node& foam, Slot radius,
                      double nodeRadius) {
  const auto net = std::dynamic_pointer_cast<const PeriodicNetworkField>(loadFieldSource(foam));
  if (!net) throw ModelError("voronoi_foam: its loader made no strut network");
  Slot field = b.sub(radius, b.external(net, p.x, p.y, p.z));
  if (nodeRadius > 0.0)
    field = b.max(field, b.sub(b.constant(nodeRadius), b.external(net->nodes(), p.x, p.y, p.z)));
  return field;
}

std::array<int, 3> foamCellsPerPeriod(const Vec3& cell, int tile) {
  const double longest = std::max({cell[0], cell[1], cell[2]});
  std::array<int, 3> cells{};
  for (int a = 0; a < 3; ++a) cells[a] = int(std::ceil(tile * longest / cell[a] - 1e-9));
  return cells;
}

NodePtr infillFoam(double cell, const Vec3& origin) {
  return makeNode("voronoi_foam",
                  {{"cell", vec3Value({cell, cell, cell})}, {"origin", vec3Value(origin)}}, {});
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
  ParamTemplate blend = realParam(
      "blend", 0.0, "length",
      "Smooth joints: how far from a joint the struts' surfaces are rounded into each other "
      "(0: sharp joints, the exact distance everywhere; with a blend the field is exact "
      "wherever no other strut is within `blend` of the nearest, and evaluates more struts).");
  range(blend, 0.0, kInf);
  ParamTemplate axis = axisParam(
      "The cylinder's axis, with conform = cylinder; the sphere's polar axis, with conform = "
      "sphere.");
  ParamTemplate around = intParam(
      "around", 12,
      "With conform = cylinder or sphere, the cells round the axis in one turn: a cell's y side "
      "is its arc at the radius where `around` cells of that side make a turn (narrower nearer "
      "the axis, wider beyond); on a sphere its z side is likewise an arc from pole to pole.");
  range(around, 3.0, 1000.0);
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
         "|q - n|)  (radius = input's value when given; with a blend k the min over the struts is "
         "m - k/2 + k / (2 sum over s of max(0, 1 - (dist(q, s) - m) / k)^2), m the min; with "
         "conform = cylinder, q is (distance from the axis, angle round it times around * "
         "cell_y / 2 pi, height along it) before the folds; with conform = sphere (distance from "
         "origin, angle round the axis times around * cell_y / 2 pi, angle from the axis times "
         "around * cell_z / 2 pi); with struts = straight, dist(p, [X(a), X(b)]) in the world "
         "for each strut [a, b], X the map from q back to the world)",
         0,
         1,
         {choiceParam("cell_type", cellIds(), "The unit cell."), size,
          positiveLength("radius", 0.1, "Radius of every strut."), nodeRadius, blend,
          vec3Param("origin", {0, 0, 0}, "length",
                    "Where a cell starts (shifts the lattice); with conform = cylinder a point "
                    "of the cylinder's axis, with conform = sphere its centre."),
          choiceParam("conform", {"none", "cylinder", "sphere"},
                      "'none': cells are boxes along x, y and z; 'cylinder': cells follow a "
                      "cylinder round `axis` through `origin` (a tube, a bone, a pipe): the "
                      "cell's x runs out from the axis, y round it and z along it, the struts "
                      "curving with it; 'sphere': cells follow spheres round `origin` (a ball, a "
                      "dome, a shell): x runs out from the centre, y round `axis` (longitude) "
                      "and z from its pole to the other (latitude), the cells narrowing towards "
                      "the poles."),
          axis, around,
          choiceParam("struts", {"curved", "straight"},
                      "With conform = cylinder or sphere: 'curved' bends each strut with its "
                      "cell; 'straight' keeps it straight from the image of one end to the "
                      "image of the other (a chord: straight beams print stiffer and go into a "
                      "3MF beam lattice one beam a strut). Cells as boxes have straight struts "
                      "either way.")},
         strutLattice,
         nullptr,
         checkStrutLattice});

  ParamTemplate seed = intParam("seed", 1,
                                "Which random foam: the same seed gives the same "
                                "foam on every machine.");
  range(seed, 0.0, 1e9);
  ParamTemplate jitter = realParam("jitter", 1.0, "",
                                   "How far a seed may stray from its cell's centre: 0 keeps it "
                                   "there (a regular foam), 1 lets it lie anywhere in its cell.");
  range(jitter, 0.0, 1.0);
  ParamTemplate tile = intParam("tile", 5,
                                "The foam repeats every `tile` times the cell's longest side "
                                "along each axis (more: a longer period, more memory).");
  range(tile, 4.0, 8.0);
  ParamTemplate spacing = size;
  spacing.doc =
      "The mean cell size along x, y and z: one seed per cell-sized box (the foam's "
      "density).";
  r.add(
      {"voronoi_foam",
       "microstructure",
       "A stochastic open-cell foam: the edges of the Voronoi diagram of random seeds, one "
       "seed jittered in each cell of a grid, each edge a capsule of the given radius (like "
       "bone or a metal foam). The seeds repeat every `tile` cells, so the foam's memory "
       "does not grow with its extent. Optional input: a field whose value replaces `radius` "
       "point by point (graded struts). Unbounded: intersect it with a part.",
       "F = radius - min over the Voronoi edges e of dist(p, e);  with node spheres "
       "F = max(F, node_radius - min over the Voronoi vertices v of |p - v|)  (radius = "
       "input's value when given; edges from CGAL's Delaunay triangulation of the seeds; "
       "with a blend the min is smooth, as strut_lattice's)",
       0,
       1,
       {spacing, positiveLength("radius", 0.08, "Radius of every strut."), nodeRadius, blend, seed,
        jitter, tile, vec3Param("origin", {0, 0, 0}, "length", "Where the seeds' grid starts.")},
       voronoiFoam,
       nullptr,
       checkVoronoiFoam});
}

}  // namespace frep

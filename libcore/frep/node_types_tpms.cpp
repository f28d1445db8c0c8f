// Triply periodic minimal surfaces (TPMS) as lattice fields for infill and microstructures.
// Each is the usual trigonometric ("nodal") approximation g of the surface, evaluated at
// q = 2 pi (p - origin) / cell. A "sheet" solid is the wall |g| <= level around the surface,
// a "network" solid the region g <= level on one side of it. `level` is in units of g (the
// fields range over about [-1.5, 1.5], Neovius over [-13, 13]); the wall is roughly
// 2 level cell / (2 pi |grad g|) thick, with |grad g| about 1 to 1.5 on the surface.
// `infill` hollows a solid to a skin and fills it with one of these lattices.
#include <algorithm>

#include "frep/node_helpers.h"
#include "frep/registry.h"
#include "frep/strut_cells.h"
#include "frep/strut_field.h"
#include "frep/tree.h"

namespace frep {

namespace {

struct Trig {
  Slot s[3], c[3];    // sin and cos of q_x, q_y, q_z
  Slot s2[3], c2[3];  // of 2 q, made on demand (Lidinoid)
};

using Surface = std::function<Slot(ProgramBuilder&, Trig&, const Point3Slots&)>;

Slot sum3(ProgramBuilder& b, Slot a, Slot c, Slot d) {
  return b.add(b.add(a, c), d);
}
Slot mul3(ProgramBuilder& b, Slot a, Slot c, Slot d) {
  return b.mul(b.mul(a, c), d);
}

// The surfaces, by id, with their documentation and nodal formula.
struct TpmsSurface {
  const char* id;
  const char* doc;
  const char* formula;
  // The typical |grad g| on the surface g = 0 (in q, the median of points sampled there):
  // what turns a length into `level` (infill's thickness).
  double gradient;
  Surface g;
};
const std::vector<TpmsSurface>& surfaces();

std::vector<ParamTemplate> latticeParams() {
  return {positiveLength("cell", 1.0, "Cell size: the period of the lattice."),
          positiveReal("level", 0.3,
                       "Half-width of a sheet wall (or the offset of a network) in units of g."),
          choiceParam("kind", {"sheet", "network"},
                      "sheet: a wall around the surface; network: the solid on one side of it."),
          vec3Param("origin", {0, 0, 0}, "length", "Where a cell starts (shifts the lattice).")};
}

// level - |g| (sheet) or level - g (network) at the context's point, with the context's
// cell, kind and origin parameters.
Slot latticeField(CompileContext& c, const Surface& surface, Slot level) {
  auto& b = c.b;
  const double k = 2.0 * kPi / c.real("cell");
  const Vec3 o = c.vec3("origin");
  const Point3Slots q = {b.affine(c.p.x, c.p.x, c.p.x, k, 0.0, 0.0, -k * o[0]),
                         b.affine(c.p.y, c.p.y, c.p.y, k, 0.0, 0.0, -k * o[1]),
                         b.affine(c.p.z, c.p.z, c.p.z, k, 0.0, 0.0, -k * o[2])};
  Trig t{};
  const Slot axes[3] = {q.x, q.y, q.z};
  for (int a = 0; a < 3; ++a) {
    t.s[a] = b.emit(Op::Sin, axes[a]);
    t.c[a] = b.emit(Op::Cos, axes[a]);
  }
  const Slot g = surface(b, t, q);
  if (c.param("kind").text == "network") return b.sub(level, g);
  return b.sub(level, b.abs(g));
}

void addTpms(Registry& r, const TpmsSurface& s) {
  r.add({s.id, "microstructure",
         std::string(s.doc) +
             " Optional input: a field whose value replaces `level` point by point (a graded "
             "lattice, e.g. walls thickening towards a surface).",
         std::string("q = 2 pi (p - origin) / cell;  g = ") + s.formula +
             ";  sheet: F = level - |g|;  network: F = level - g  (level = input's value when "
             "given)",
         0, 1, latticeParams(), [g = s.g](CompileContext& c) {
           const Slot level = c.inputCount() ? c.input(0) : c.b.constant(c.real("level"));
           return latticeField(c, g, level);
         }});
}

std::vector<std::string> surfaceIds() {
  std::vector<std::string> ids;
  for (const TpmsSurface& s : surfaces()) ids.push_back(s.id);
  return ids;
}

// An infill's lattices: the surfaces, then each strut lattice's unit cell as CELL_struts, then
// the Voronoi foam.
constexpr const char* kStrutsSuffix = "_struts";
constexpr const char* kFoam = "voronoi_struts";
std::vector<std::string> infillLatticeIds() {
  std::vector<std::string> ids = surfaceIds();
  for (const UnitCell& c : unitCells()) ids.push_back(c.id + kStrutsSuffix);
  ids.push_back(kFoam);
  return ids;
}
// The unit cell of an infill's CELL_struts, else nullptr.
const UnitCell* strutCellOf(const std::string& lattice) {
  for (const UnitCell& c : unitCells())
    if (lattice == c.id + kStrutsSuffix) return &c;
  return nullptr;
}

// A part needs a few drain holes; the limit keeps the field's program small.
constexpr std::size_t kMostDrainHoles = 100;

// The union of the drain holes' cylinders (> 0 inside one): each along drain_axis through its
// point, of radius drain_diameter / 2, reaching wall + drain_diameter / 2 to either side: a
// hole placed on the skin's outer or inner surface pierces it, also where it meets the skin at
// a slant, and reaches little of the skin beside it (a hole by a corner cuts the side walls
// only that far).
Slot drainHoles(CompileContext& c, const std::vector<Vec3>& holes) {
  auto& b = c.b;
  const double radius = 0.5 * c.real("drain_diameter");
  const double reach = c.real("wall") + radius;
  const Frame frame = frameAlong(c.vec3("drain_axis"));
  Slot all = 0;
  for (std::size_t i = 0; i < holes.size(); ++i) {
    const Point3Slots q = localCoordinates(b, c.p, holes[i], frame);
    const Slot across = b.sqrt(b.add(b.sqr(q.x), b.sqr(q.y)));
    const Slot hole =
        b.min(b.sub(b.constant(radius), across), b.sub(b.constant(reach), b.abs(q.z)));
    all = i == 0 ? hole : b.max(all, hole);
  }
  return all;
}

void addInfill(Registry& r) {
  std::vector<ParamTemplate> params = {
      choiceParam(
          "lattice", infillLatticeIds(),
          "The lattice filling the inside: a TPMS (sheet or network) or a strut lattice "
          "(CELL_struts: strut_lattice's unit cells, `thickness` the struts' diameter) or a "
          "Voronoi foam (voronoi_struts: voronoi_foam's, seeds in cubes of `cell`)."),
      positiveLength("wall", 0.1, "Thickness of the solid skin kept inside the surface.")};
  for (const ParamTemplate& p : latticeParams()) params.push_back(p);
  ParamTemplate thickness = realParam(
      "thickness", 0.0, "length",
      "The lattice's sheet thickness (sheet), or how far a network's surface moves out "
      "(network), in model units; it sets `level` from the surface's typical gradient. 0: "
      "`level` as given. For a strut lattice the struts' diameter (0: a fifth of the cell).");
  params.push_back(range(thickness, 0.0, kInf));
  ParamTemplate holes = pointsParam(
      "drain_holes", {}, 0, "length",
      "Where holes pierce the skin so that resin or powder can leave the lattice: each a "
      "cylinder through the point along drain_axis, reaching wall + drain_diameter / 2 to "
      "either side (place it on the skin, e.g. where the printability report says a cavity "
      "drains). Empty: no holes.");
  holes.maxPoints = kMostDrainHoles;
  params.push_back(holes);
  params.push_back(positiveLength("drain_diameter", 0.5, "Diameter of every drain hole."));
  ParamTemplate drainAxis = axisParam("Direction of the drain holes' cylinders.");
  drainAxis.name = "drain_axis";
  params.push_back(drainAxis);
  r.add({"infill", "microstructure",
         "Hollows a solid to a skin of the given wall thickness and fills its inside with a "
         "lattice: light, printable infill that follows the part's shape; drain holes open "
         "the skin where a resin or powder printer must empty it.",
         "F = max(min(f, wall - f, -H), min(f, lattice));  H = max over drain holes of "
         "min(drain_diameter/2 - distance to its axis, wall + drain_diameter/2 - |distance "
         "along it|) (no holes: no -H);  lattice as its surface's node with level = "
         "pi thickness |grad g| / cell (sheet) or 2 pi thickness |grad g| / cell (network) when "
         "thickness > 0;  a strut lattice (CELL_struts): lattice = thickness / 2 - the distance "
         "to the cell's struts (cubes of `cell`; radius cell / 10 when thickness = 0), or to the "
         "edges of voronoi_foam's foam (voronoi_struts: seeds in cubes of `cell`)",
         1, 1, params,
         [](CompileContext& c) {
           auto& b = c.b;
           const std::string& id = c.param("lattice").text;
           const Slot f = c.input(0);
           const Slot skin = b.min(f, b.sub(b.constant(c.real("wall")), f));
           const std::vector<Vec3> holes = pointsOf(c.param("drain_holes"));
           const Slot opened = holes.empty() ? skin : b.min(skin, b.neg(drainHoles(c, holes)));
           const double size = c.real("cell"), t = c.real("thickness");
           const Slot radius = b.constant(t > 0.0 ? 0.5 * t : 0.1 * size);
           if (const UnitCell* cell = strutCellOf(id)) {
             const Slot lattice = strutLatticeField(b, c.p, *cell, {size, size, size},
                                                    c.vec3("origin"), radius, 0.0);
             return b.max(opened, b.min(f, lattice));
           }
           if (id == kFoam) {
             const Slot lattice =
                 voronoiFoamField(b, c.p, *infillFoam(size, c.vec3("origin")), radius, 0.0);
             return b.max(opened, b.min(f, lattice));
           }
           const auto found = std::find_if(surfaces().begin(), surfaces().end(),
                                           [&](const TpmsSurface& s) { return id == s.id; });
           // a sheet is 2 level cell / (2 pi |grad g|) thick; a network's surface moves out
           // by level cell / (2 pi |grad g|)
           const double perLevel = c.real("cell") / (2.0 * kPi * found->gradient);
           const bool sheet = c.param("kind").text == "sheet";
           const double level = t > 0.0 ? t / (sheet ? 2.0 : 1.0) / perLevel : c.real("level");
           const Slot lattice = latticeField(c, found->g, b.constant(level));
           return b.max(opened, b.min(f, lattice));
         },
         [](const Node&, const std::vector<Box3>& in) { return in[0]; }});
}

const std::vector<TpmsSurface>& surfaces() {
  static const std::vector<TpmsSurface> table = {
      {"gyroid",
       "Schoen's gyroid lattice: one connected wall, no straight lines; the most used TPMS for "
       "infill.",
       "sin qx cos qy + sin qy cos qz + sin qz cos qx", 1.50,
       [](ProgramBuilder& b, Trig& t, const Point3Slots&) {
         return sum3(b, b.mul(t.s[0], t.c[1]), b.mul(t.s[1], t.c[2]), b.mul(t.s[2], t.c[0]));
       }},
      {"schwarz_p", "Schwarz's primitive (P) lattice: channels along the three axes.",
       "cos qx + cos qy + cos qz", 1.27,
       [](ProgramBuilder& b, Trig& t, const Point3Slots&) {
         return sum3(b, t.c[0], t.c[1], t.c[2]);
       }},
      {"schwarz_d", "Schwarz's diamond (D) surface, in its four-term nodal form.",
       "sin qx sin qy sin qz + sin qx cos qy cos qz + cos qx sin qy cos qz + cos qx cos qy sin qz",
       1.45,
       [](ProgramBuilder& b, Trig& t, const Point3Slots&) {
         return b.add(sum3(b, mul3(b, t.s[0], t.s[1], t.s[2]), mul3(b, t.s[0], t.c[1], t.c[2]),
                           mul3(b, t.c[0], t.s[1], t.c[2])),
                      mul3(b, t.c[0], t.c[1], t.s[2]));
       }},
      {"diamond",
       "The diamond lattice in the two-term form common in lattice tools (the D surface with "
       "another phase than schwarz_d).",
       "cos qx cos qy cos qz - sin qx sin qy sin qz", 1.03,
       [](ProgramBuilder& b, Trig& t, const Point3Slots&) {
         return b.sub(mul3(b, t.c[0], t.c[1], t.c[2]), mul3(b, t.s[0], t.s[1], t.s[2]));
       }},
      {"neovius", "Neovius' surface: Schwarz P's channels with extra openings.",
       "3 (cos qx + cos qy + cos qz) + 4 cos qx cos qy cos qz", 2.57,
       [](ProgramBuilder& b, Trig& t, const Point3Slots&) {
         const Slot sum = sum3(b, t.c[0], t.c[1], t.c[2]);
         const Slot prod = mul3(b, t.c[0], t.c[1], t.c[2]);
         return b.affine(sum, prod, prod, 3.0, 4.0, 0.0, 0.0);
       }},
      {"lidinoid", "Lidin's lidinoid: a gyroid relative with wavier channels.",
       "(sin 2qx cos qy sin qz + sin 2qy cos qz sin qx + sin 2qz cos qx sin qy) / 2 - "
       "(cos 2qx cos 2qy + cos 2qy cos 2qz + cos 2qz cos 2qx) / 2 + 0.15",
       1.12,
       [](ProgramBuilder& b, Trig& t, const Point3Slots& q) {
         const Slot axes[3] = {q.x, q.y, q.z};
         for (int a = 0; a < 3; ++a) {
           const Slot twice = b.affine(axes[a], axes[a], axes[a], 2.0, 0.0, 0.0, 0.0);
           t.s2[a] = b.emit(Op::Sin, twice);
           t.c2[a] = b.emit(Op::Cos, twice);
         }
         const Slot waves =
             sum3(b, mul3(b, t.s2[0], t.c[1], t.s[2]), mul3(b, t.s2[1], t.c[2], t.s[0]),
                  mul3(b, t.s2[2], t.c[0], t.s[1]));
         const Slot pairs =
             sum3(b, b.mul(t.c2[0], t.c2[1]), b.mul(t.c2[1], t.c2[2]), b.mul(t.c2[2], t.c2[0]));
         return b.affine(waves, pairs, pairs, 0.5, -0.5, 0.0, 0.15);
       }},
  };
  return table;
}

}  // namespace

void registerMicrostructures(Registry& r) {
  for (const TpmsSurface& s : surfaces()) addTpms(r, s);
  addInfill(r);
}

}  // namespace frep

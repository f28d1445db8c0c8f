#include "pipeline/beam_export.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>

#include "base/errors.h"
#include "frep/ffd_field.h"
#include "frep/field_sources.h"
#include "frep/interval.h"
#include "frep/node_helpers.h"
#include "frep/periodic_segments.h"
#include "frep/registry.h"
#include "frep/strut_cells.h"
#include "frep/strut_field.h"
#include "io/three_mf_stream.h"
#include "lattice/ffd_lattice.h"
#include "pipeline/finished_mesh.h"

namespace frep {

namespace {

constexpr const char* kStrutsSuffix = "_struts";

// What the beams are: the lattice's cells, radius (constant or a field) and the part that
// clips them; for an infill the skin printed beside them.
struct BeamSource {
  std::function<std::vector<StrutPiece>(const Box3&)> strutsIn;  // each strut meeting a box once
  // Conformal cells: strutsIn gives the struts in the lattice's coordinates and this maps
  // those to the world (each strut then curves and is written as a chain of straight beams);
  // null: the struts are straight and in world coordinates.
  std::function<Vec3(const Vec3&)> toWorld;
  // Bent by an ffd: the lattice's own space is the rest box, where its radius's field is read
  // (at the struts' ends before toWorld); otherwise at their ends in the world.
  bool bent = false;
  // The share of chainTolerance the chains of toWorld take (conformal cells bent by an ffd
  // are chained twice).
  double chainShare = 1.0;
  // How many times a strut may be halved into a chain (0: every strut one beam; an ffd's
  // straight struts are straight from one end's image to the other's).
  int chainDepth = 5;
  double smallestCell = 1.0;
  double radius = 0.0;
  NodePtr grading;    // the radius's field, or null
  NodePtr part;       // clips the beams
  NodePtr skin;       // an infill's skin, or null
  double wall = 0.0;  // the skin's thickness
  double nodeRadius = 0.0;
};

void setCells(BeamSource& s, const UnitCell& cell, const Vec3& size, const Vec3& origin) {
  s.strutsIn = [&cell, size, origin](const Box3& box) {
    return strutsInBox(cell, size, origin, box);
  };
  s.smallestCell = std::min({size[0], size[1], size[2]});
}

void setFoam(BeamSource& s, const Node& foam) {
  const auto net = std::dynamic_pointer_cast<const PeriodicSegmentsField>(loadFieldSource(foam));
  if (!net) throw ModelError("voronoi_foam: its loader made no strut network");
  s.strutsIn = [net](const Box3& box) { return net->segmentsInBox(box); };
  const Vec3 size = foam.vec3("cell");
  s.smallestCell = std::min({size[0], size[1], size[2]});
}

// The lattice's coordinates of a strut_lattice that follows a cylinder or a sphere (as
// strutLattice in node_types_struts.cpp computes them) and back: strutsIn takes a world box to
// the coordinates' box that holds it (a whole turn round the axis, pole to pole) and keeps each
// strut once across the angle's cut (by its middle) and, on a sphere, the part of it between
// the poles.
void setConformal(BeamSource& s, const Node& lattice) {
  const UnitCell& cell = unitCell(lattice.param("cell_type").text);
  const Vec3 size = lattice.vec3("cell"), origin = lattice.vec3("origin");
  const Frame f = frameAlong(lattice.vec3("axis"));
  const bool sphere = lattice.param("conform").text == "sphere";
  const double perTurn = lattice.real("around") / (2.0 * kPi);
  const double alongY = perTurn * size[1], alongZ = perTurn * size[2];  // arc per radian
  const double halfTurn = kPi * alongY, pole = kPi * alongZ;
  s.smallestCell = std::min({size[0], size[1], size[2]});
  if (lattice.param("struts").text == "straight") s.chainDepth = 0;  // chords, as the field's
  s.toWorld = [=](const Vec3& q) {
    const double angle = q[1] / alongY;
    Vec3 local;
    if (sphere) {
      const double fromPole = q[2] / alongZ;
      local = {q[0] * std::sin(fromPole) * std::cos(angle),
               q[0] * std::sin(fromPole) * std::sin(angle), q[0] * std::cos(fromPole)};
    } else {
      local = {q[0] * std::cos(angle), q[0] * std::sin(angle), q[2]};
    }
    return vadd(origin,
                vadd(vscale(f.u, local[0]), vadd(vscale(f.v, local[1]), vscale(f.w, local[2]))));
  };
  s.strutsIn = [=, &cell](const Box3& world) {
    double farthest = 0.0, lowest = HUGE_VAL, highest = -HUGE_VAL;
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 p{corner & 1 ? world.hi[0] : world.lo[0], corner & 2 ? world.hi[1] : world.lo[1],
                   corner & 4 ? world.hi[2] : world.lo[2]};
      const Vec3 d = vsub(p, origin);
      const double u = vdot(d, f.u), v = vdot(d, f.v), w = vdot(d, f.w);
      farthest = std::max(farthest, std::sqrt(u * u + v * v + (sphere ? w * w : 0.0)));
      lowest = std::min(lowest, w);
      highest = std::max(highest, w);
    }
    const Box3 coordinates{{0.0, -halfTurn, sphere ? 0.0 : lowest},
                           {farthest, halfTurn, sphere ? pole : highest}};
    std::vector<StrutPiece> kept;
    for (const StrutPiece& p : strutsInBox(cell, size, {0, 0, 0}, coordinates)) {
      const double middle = 0.5 * (p.a[1] + p.b[1]);
      if (middle < -halfTurn || middle >= halfTurn) continue;  // its copy a turn away is kept
      // the part out from the axis or centre and, on a sphere, between the poles (the
      // field's distance is at least 0 and its latitude in [0, pole])
      StrutPiece piece = p;
      if (!clip(p.a, p.b, {0.0, -HUGE_VAL, sphere ? 0.0 : -HUGE_VAL},
                {HUGE_VAL, HUGE_VAL, sphere ? pole : HUGE_VAL}, &piece))
        continue;
      kept.push_back(piece);
    }
    return kept;
  };
}

// A beam: its ends in the world, and where the radius's field is read for each.
struct Beam {
  StrutPiece world, radiusAt;
};

// A strut of conformal cells (a, b in the lattice's coordinates) as world segments whose chain
// stays within `tolerance` of its curve: halved where the curve's middle is farther than that
// from the chord, at most 5 times. Each piece's ends in the lattice's coordinates go with it
// (a bent lattice's radius is read there).
void curveAsSegments(const std::function<Vec3(const Vec3&)>& toWorld, const Vec3& a, const Vec3& b,
                     const Vec3& wa, const Vec3& wb, double tolerance, int depth,
                     std::vector<Beam>& out) {
  const Vec3 m = vscale(vadd(a, b), 0.5), wm = toWorld(m);
  if (depth > 0 && distanceToSegment(wm, wa, wb) > tolerance) {
    curveAsSegments(toWorld, a, m, wa, wm, tolerance, depth - 1, out);
    curveAsSegments(toWorld, m, b, wm, wb, tolerance, depth - 1, out);
    return;
  }
  out.push_back({{wa, wb}, {a, b}});
}

// The chains' tolerance: a tenth of the strut radius (a hundredth of a cell for struts of a
// field's radius).
double chainTolerance(const BeamSource& s) {
  return s.radius > 0.0 ? 0.1 * s.radius : 0.01 * s.smallestCell;
}

// A strut lattice (or foam) bent by an ffd node: the struts `s` already gives in the rest
// box, each cut to it and mapped by the lattice's deformation. Those outside are left out:
// where the bent lattice covers them the field shows the bent struts instead, and a part the
// beams serve lies in the bent lattice (docs/struts.md). Cells conformal to a cylinder or
// sphere curve first: each strut becomes a chain in the lattice's own space (within half the
// tolerance, the bend's chains taking the other half), whose pieces are cut to the rest box.
void setBent(BeamSource& s, const Node& ffd) {
  const auto bend = std::make_shared<const FfdLattice>(ffdLatticeOf(ffd));
  const Box3 rest = bend->rest();
  const double half = 0.5 * chainTolerance(s);
  s.strutsIn = [rest, unbent = s.strutsIn, conformal = s.toWorld, half,
                depth = s.chainDepth](const Box3&) {
    std::vector<StrutPiece> pieces;
    std::vector<Beam> chain;
    StrutPiece piece;
    for (const StrutPiece& p : unbent(rest)) {
      chain.clear();
      if (conformal)
        curveAsSegments(conformal, p.a, p.b, conformal(p.a), conformal(p.b), half, depth, chain);
      else
        chain.push_back({p, p});
      for (const Beam& c : chain)
        if (clip(c.world.a, c.world.b, rest.lo, rest.hi, &piece)) pieces.push_back(piece);
    }
    return pieces;
  };
  if (s.toWorld) s.chainShare = 0.5;
  s.chainDepth = ffd.param("struts").text == "straight" ? 0 : 5;  // (cells as boxes: checked)
  s.toWorld = [bend](const Vec3& q) { return bend->deform(q); };
  s.bent = true;
}

BeamSource sourceOf(const NodePtr& root) {
  const std::string what =
      "a 3MF beam lattice needs a strut lattice: the model's root must be the intersection "
      "of a strut_lattice or voronoi_foam and a part (the strut_lattice may be bent by an "
      "ffd), or an infill whose lattice is a strut lattice (CELL_struts or voronoi_struts)";
  BeamSource s;
  const std::string& type = root->type->id;
  if (type == "intersection" && root->inputs.size() == 2) {
    for (int k = 0; k < 2; ++k) {
      NodePtr lattice = root->inputs[k];
      NodePtr bent;  // an ffd node bending the lattice, or null
      if (lattice->type->id == "ffd" && lattice->inputs.size() == 1) {
        bent = lattice;
        lattice = lattice->inputs[0];
      }
      const std::string& id = lattice->type->id;
      if (id == "strut_lattice" && lattice->param("conform").text != "none")
        setConformal(s, *lattice);
      else if (id == "strut_lattice")
        setCells(s, unitCell(lattice->param("cell_type").text), lattice->vec3("cell"),
                 lattice->vec3("origin"));
      else if (id == "voronoi_foam")
        setFoam(s, *lattice);
      else
        continue;
      s.radius = lattice->real("radius");
      s.nodeRadius = lattice->real("node_radius");
      if (!lattice->inputs.empty()) s.grading = lattice->inputs[0];
      if (bent) setBent(s, *bent);
      s.part = root->inputs[1 - k];
      return s;
    }
  } else if (type == "ffd" && root->inputs.size() == 1 &&
             root->inputs[0]->type->id == "intersection") {
    // the lattice cut to a part, both bent: the bent part clips the bent struts
    BeamSource s = sourceOf(root->inputs[0]);
    setBent(s, *root);
    s.part = makeNode("ffd", root->params, {s.part});
    return s;
  } else if (type == "infill") {
    const std::string& lattice = root->param("lattice").text;
    const std::size_t n = lattice.size(), m = std::string(kStrutsSuffix).size();
    if (n > m && lattice.compare(n - m, m, kStrutsSuffix) == 0) {
      const double cell = root->real("cell"), t = root->real("thickness");
      if (lattice == "voronoi_struts")
        setFoam(s, *infillFoam(cell, root->vec3("origin")));
      else
        setCells(s, unitCell(lattice.substr(0, n - m)), {cell, cell, cell}, root->vec3("origin"));
      s.radius = t > 0.0 ? 0.5 * t : 0.1 * cell;
      s.part = root->inputs.at(0);
      s.wall = root->real("wall");
      s.skin = makeNode("shell", {{"thickness", realValue(s.wall)}}, {s.part});
      return s;
    }
    throw ModelError(what + "; this infill's lattice is '" + lattice + "'");
  }
  throw ModelError(what + "; it is " + type);
}

// Whether the part may reach within `grow` of the segment [a, b]: its interval over the
// segment's box grown by `grow` is not all below 0, on the whole or, where undecided, on one of
// the halves, `depth` times (a diagonal strut's box is mostly air).
bool mayReach(const Program& part, const Vec3& a, const Vec3& b, double grow, int depth) {
  Interval box[3];
  for (int k = 0; k < 3; ++k)
    box[k] = Interval(std::min(a[k], b[k]) - grow, std::max(a[k], b[k]) + grow);
  const Interval v = part.evalInterval(box[0], box[1], box[2]);
  if (v.hi < 0.0) return false;
  if (v.lo >= 0.0 || depth == 0) return true;
  const Vec3 m = vscale(vadd(a, b), 0.5);
  return mayReach(part, a, m, grow, depth - 1) || mayReach(part, m, b, grow, depth - 1);
}

// The part's mesh or an infill's skin. Unless the settings give a tolerance, it is simplified
// within a tenth of a cell: a beam file exists to be small, and the mesher's mesh of a plain
// skin at the export's resolution is most of it (docs/struts.md). Where the simplified mesh is
// not printable, the mesher's own mesh is written.
TriangleMesh meshOf(const NodePtr& node, const MeshingBox& box, const MeshSettings& settings,
                    const std::function<bool(double)>& progress, double& tolerance,
                    CheckReport& report) {
  MeshingOptions o;
  o.bbox = box.box;
  o.resolution = box.resolution;
  o.settings = settings;
  if (!o.settings.tolerance) o.settings.tolerance = 0.1 * box.resolution;
  o.normals = false;
  FinishedMesh finished = meshAndFinish(compile(node), o, progress, true);
  report = checkMesh(finished.mesh);
  tolerance = finished.simplified ? *o.settings.tolerance : 0.0;
  if (finished.simplified && !report.printable()) {
    const CheckReport meshers = checkMesh(finished.meshers);
    if (meshers.printable()) {
      report = meshers;
      tolerance = 0.0;
      return std::move(finished.meshers);
    }
  }
  return std::move(finished.mesh);
}

// The runs of the strut [a, b] where `inside` >= 0, sampled every `step` along it, each end at
// a crossing found by bisection: where an infill's struts lie deep enough in the part that
// their caps stay in the skin.
std::vector<StrutPiece> insideRuns(const Program& part, double depth, const Vec3& a, const Vec3& b,
                                   double step) {
  auto at = [&](double t) { return vadd(a, vscale(vsub(b, a), t)); };
  auto inside = [&](double t) {
    const Vec3 p = at(t);
    return part.eval(p[0], p[1], p[2]) - depth >= 0.0;
  };
  auto crossing = [&](double in, double out) {  // inside(in), !inside(out)
    for (int k = 0; k < 40; ++k) {
      const double m = 0.5 * (in + out);
      (inside(m) ? in : out) = m;
    }
    return in;
  };
  const int n = std::max(1, int(std::ceil(vlength(vsub(b, a)) / step)));
  std::vector<StrutPiece> runs;
  bool was = inside(0.0);
  double from = 0.0;
  for (int i = 1; i <= n; ++i) {
    const double t = double(i) / n;
    const bool is = inside(t);
    if (is && !was) from = crossing(t, double(i - 1) / n);
    if (!is && was) {
      const double to = crossing(double(i - 1) / n, t);
      if (to > from) runs.push_back({at(from), at(to)});
    }
    was = is;
  }
  if (was) runs.push_back({at(from), b});
  return runs;
}

void addMesh(ThreeMfStreamWriter& w, const std::string& name, const TriangleMesh& mesh,
             bool buildItem) {
  w.beginObject(name, buildItem);
  for (const Vec3f& p : mesh.positions) w.vertex(p);
  w.closeVertices();
  for (const Triangle& t : mesh.triangles) w.triangle(t);
  w.endObject();
}

}  // namespace

BeamExportResult exportBeamLattice(const NodePtr& root, const MeshingBox& box,
                                   const MeshSettings& settings, const ThreeMfOptions& options,
                                   const std::string& name, const std::string& path, bool force,
                                   const std::function<bool(double)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  const BeamSource source = sourceOf(root);
  BeamExportResult r;
  auto stage = [&](double from, double to) -> std::function<bool(double)> {
    if (!progress) return nullptr;
    return [=](double f) { return progress(from + (to - from) * f); };
  };
  // The part's mesh clips the beams, or, for an infill, the beams end in the middle of its
  // skin (printed beside them), so that no clipping mesh is needed. Both must be sound.
  TriangleMesh clip, skin;
  if (source.skin) {
    skin = meshOf(source.skin, box, settings, stage(0.0, 0.8), r.meshTolerance, r.skinReport);
    r.skinTriangles = skin.triangleCount();
  } else {
    clip = meshOf(source.part, box, settings, stage(0.0, 0.8), r.meshTolerance, r.clipReport);
    r.clipped = true;
    r.clipTriangles = clip.triangleCount();
  }
  const CheckReport& judged = source.skin ? r.skinReport : r.clipReport;
  if (!force && !judged.printable()) return r;
  if (source.nodeRadius > 0.0)
    r.notes = "the node spheres are not written (the beam lattice has beams only)";

  // The beams: every strut of the cells round the part's mesh that the part may reach (its
  // interval over the strut's box, grown by the radius, not all below 0).
  Box3 reach{{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
  for (const Vec3f& p : (source.skin ? skin : clip).positions)
    for (int a = 0; a < 3; ++a) {
      reach.lo[a] = std::min(reach.lo[a], double(p[a]));
      reach.hi[a] = std::max(reach.hi[a], double(p[a]));
    }
  const Program part = compile(source.part);
  const Program grading = source.grading ? compile(source.grading) : Program();
  const double minLength = 1e-4 * source.smallestCell;
  BeamLattice3mf lattice;
  lattice.radius = source.radius;
  lattice.minLength = minLength;
  std::vector<Vec3f> vertices;
  // Struts meeting at a node share its vertex: their ends, rounded to a millionth of a cell,
  // are equal (a foam's copies of a node moved by its period differ in the last bits).
  std::map<std::array<long long, 3>, std::uint32_t> vertexOf;
  const double snap = 1e-6 * source.smallestCell;
  auto vertex = [&](const Vec3& p) {
    const std::array<long long, 3> key{std::llround(p[0] / snap), std::llround(p[1] / snap),
                                       std::llround(p[2] / snap)};
    const auto [at, added] = vertexOf.emplace(key, static_cast<std::uint32_t>(vertices.size()));
    if (added)
      vertices.push_back(
          {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
    return at->second;
  };
  // An infill's beams: the runs deeper in the part than half the skin (and than the radius),
  // so that a beam's end and its round cap lie in the skin.
  const double depth = std::max(0.5 * source.wall, 1.01 * source.radius);
  // Conformal cells' struts curve: each is a chain of straight beams, within a tenth of the
  // radius of its curve.
  std::vector<Beam> pieces;
  const double curveTolerance = source.chainShare * chainTolerance(source);
  for (const StrutPiece& c : source.strutsIn(reach)) {
    if (source.toWorld)
      curveAsSegments(source.toWorld, c.a, c.b, source.toWorld(c.a), source.toWorld(c.b),
                      curveTolerance, source.chainDepth, pieces);
    else
      pieces.push_back({c, c});
  }
  std::vector<Beam> struts;
  for (Beam b : pieces) {
    if (!source.bent) b.radiusAt = b.world;
    if (!source.skin) {
      struts.push_back(b);
      continue;
    }
    // (an infill's struts: straight, in the world, of one radius)
    const StrutPiece& s = b.world;
    if (!mayReach(part, s.a, s.b, 0.0, 4)) continue;
    for (const StrutPiece& run : insideRuns(part, depth, s.a, s.b, 0.25 * source.wall))
      struts.push_back({run, run});
  }
  for (const Beam& b : struts) {
    const StrutPiece& s = b.world;
    double r1 = 0.0, r2 = 0.0;
    if (source.grading) {
      const StrutPiece& at = b.radiusAt;
      r1 = grading.eval(at.a[0], at.a[1], at.a[2]);
      r2 = grading.eval(at.b[0], at.b[1], at.b[2]);
      if (!(r1 > 0.0) && !(r2 > 0.0)) continue;  // no strut there
      r1 = std::max(r1, minLength);
      r2 = std::max(r2, minLength);
    }
    if (!mayReach(part, s.a, s.b, std::max({source.radius, r1, r2}), 4)) continue;
    const std::uint32_t v1 = vertex(s.a), v2 = vertex(s.b);
    if (v1 == v2) continue;  // (a strut shorter than a float's step)
    lattice.beams.push_back({v1, v2, r1, r2});
  }
  r.beams = lattice.beams.size();
  r.vertices = vertices.size();
  if (lattice.beams.empty())
    throw ModelError(name + ": no strut of the lattice reaches the part; nothing to write");
  if (progress && !progress(0.85)) throw Cancelled();

  ThreeMfOptions o = options;
  o.beamLattice = true;
  ThreeMfStreamWriter writer(
      path, o,
      expectedXmlBytes(clip.positions.size() + skin.positions.size() + vertices.size(),
                       clip.triangleCount() + skin.triangleCount() + lattice.beams.size()));
  if (r.clipped) {
    addMesh(writer, name + " clipping mesh", clip, false);
    lattice.clippingObject = writer.objectId();
  }
  if (source.skin) addMesh(writer, name + " skin", skin, true);
  writer.beginObject(name + " struts", true);
  for (const Vec3f& p : vertices) writer.vertex(p);
  writer.beams(lattice);
  writer.endObject();
  writer.finish()->commit();
  r.written = true;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

std::string beamExportSummary(const BeamExportResult& r) {
  std::string text =
      std::to_string(r.beams) + " beams on " + std::to_string(r.vertices) + " vertices, ";
  const std::string within =
      r.meshTolerance > 0.0 ? ", simplified within " + numberText(r.meshTolerance) : "";
  if (r.clipped)
    return text + "clipped by the part's mesh (" + std::to_string(r.clipTriangles) + " triangles" +
           within + ")";
  return text + "ending in the middle of the skin (" + std::to_string(r.skinTriangles) +
         " triangles" + within + ")";
}

}  // namespace frep

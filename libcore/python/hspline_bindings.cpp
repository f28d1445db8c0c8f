// frepcore's hsplines: the HSpline class and .hs / STEP files. CVs are (level, i, j)
// tuples; errors arrive as ValueError (a refused request) or OSError (a file).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tuple>

#include "base/errors.h"
#include "frep/model_json.h"
#include "hspline/hs_file.h"
#include "hspline/hspline.h"
#include "hspline/hspline_attach.h"
#include "hspline/hspline_envelope.h"
#include "hspline/hspline_flatten.h"
#include "hspline/hspline_select.h"
#include "hspline/hspline_shapes.h"
#include "hspline/hspline_tessellate.h"
#include "hspline/occt/occ_hspline.h"
#include "pipeline/hspline_shell.h"
#include "python/binding_helpers.h"
#include "python/bindings.h"

namespace py = pybind11;

namespace frep {

namespace {

using CvTuple = std::tuple<int, int, int>;

std::vector<HsCvRef> refs(const std::vector<CvTuple>& cvs) {
  std::vector<HsCvRef> out;
  for (const auto& [l, i, j] : cvs) out.push_back({l, i, j});
  return out;
}

std::vector<CvTuple> tuples(const std::vector<HsCvRef>& cvs) {
  std::vector<CvTuple> out;
  for (const HsCvRef& c : cvs) out.emplace_back(c.level, c.i, c.j);
  return out;
}

SplineAxis axisOf(std::vector<double> knots, double period, const char* what) {
  return period > 0 ? SplineAxis::periodic(std::move(knots), period, what)
                    : SplineAxis::open(std::move(knots), what);
}

py::dict summaryDict(const OccShapeSummary& s) {
  py::dict d;
  d["solids"] = s.solids, d["shells"] = s.shells, d["faces"] = s.faces;
  d["valid"] = s.valid, d["volume"] = s.volume, d["area"] = s.area;
  return d;
}

py::dict pointDict(const HsSurfacePoint& p) {
  py::dict d;
  d["point"] = p.position, d["normal"] = p.normal(), d["du"] = p.du, d["dv"] = p.dv;
  return d;
}

}  // namespace

void bindHSpline(py::module_& m) {
  py::class_<HSpline>(
      m, "HSpline",
      "A hierarchical B-spline surface (seed 003): bicubic level 0 and finer levels whose "
      "CVs are offsets in the parent's frame. CVs are (level, i, j).")
      .def_static("plane", &hsplinePlane, py::arg("cvs_u"), py::arg("cvs_v"), py::arg("size_u"),
                  py::arg("size_v"))
      .def_static("cylinder", &hsplineCylinder, py::arg("cvs_around"), py::arg("cvs_along"),
                  py::arg("radius"), py::arg("height"))
      .def_static("torus", &hsplineTorus, py::arg("cvs_around"), py::arg("cvs_tube"),
                  py::arg("major_radius"), py::arg("minor_radius"))
      .def_static(
          "from_grid",
          [](std::vector<double> ku, double pu, std::vector<double> kv, double pv,
             std::vector<Vec3> positions) {
            return HSpline(axisOf(std::move(ku), pu, "knots_u"),
                           axisOf(std::move(kv), pv, "knots_v"), std::move(positions));
          },
          py::arg("knots_u"), py::arg("period_u"), py::arg("knots_v"), py::arg("period_v"),
          py::arg("positions"),
          "Level 0 from knots (period 0: an open axis of CVs + 4 knots; > 0: periodic, CVs knots "
          "in one period) and nu x nv positions (u fastest).")
      .def_static(
          "from_arrays",
          [](std::vector<double> ku, double pu, std::vector<double> kv, double pv,
             const std::vector<int>& levels, const std::vector<int>& is, const std::vector<int>& js,
             const std::vector<Vec3>& values) {
            if (levels.size() != is.size() || is.size() != js.size() || js.size() != values.size())
              throw ModelError("hspline: the CV arrays differ in length (levels " +
                               std::to_string(levels.size()) + ", i " + std::to_string(is.size()) +
                               ", j " + std::to_string(js.size()) + ", values " +
                               std::to_string(values.size()) + ")");
            std::vector<std::vector<HsCv>> byLevel;
            for (std::size_t k = 0; k < levels.size(); ++k) {
              if (levels[k] < 0 || levels[k] >= HSpline::kMaxLevels)
                throw ModelError("hspline: CV " + std::to_string(k) + " names level " +
                                 std::to_string(levels[k]) + "; levels are 0 to " +
                                 std::to_string(HSpline::kMaxLevels - 1));
              if (byLevel.size() <= static_cast<std::size_t>(levels[k]))
                byLevel.resize(static_cast<std::size_t>(levels[k]) + 1);
              byLevel[static_cast<std::size_t>(levels[k])].push_back({is[k], js[k], values[k]});
            }
            return HSpline::fromLevels(axisOf(std::move(ku), pu, "knots_u"),
                                       axisOf(std::move(kv), pv, "knots_v"), std::move(byLevel));
          },
          py::arg("knots_u"), py::arg("period_u"), py::arg("knots_v"), py::arg("period_v"),
          py::arg("levels"), py::arg("i"), py::arg("j"), py::arg("values"),
          "The hierarchy from flat arrays, as to_arrays() gives them (how a FreeCAD feature stores "
          "it).")
      .def(
          "to_arrays",
          [](const HSpline& h, bool valuesOnly) {
            py::dict d;
            if (valuesOnly) {  // tuples: what a FreeCAD vector list property takes as it is
              std::vector<std::tuple<double, double, double>> values;
              for (int l = 0; l < h.levelCount(); ++l)
                for (const HsCv& cv : h.level(l).cvs)
                  values.emplace_back(cv.value[0], cv.value[1], cv.value[2]);
              d["values"] = values;
              return d;
            }
            const HsLevel& base = h.level(0);
            d["knots_u"] = base.u.knots(),
            d["period_u"] = base.u.isPeriodic() ? base.u.period() : 0.0;
            d["knots_v"] = base.v.knots(),
            d["period_v"] = base.v.isPeriodic() ? base.v.period() : 0.0;
            std::vector<int> levels, is, js;
            std::vector<Vec3> values;
            for (int l = 0; l < h.levelCount(); ++l)
              for (const HsCv& cv : h.level(l).cvs)
                levels.push_back(l), is.push_back(cv.i), js.push_back(cv.j),
                    values.push_back(cv.value);
            d["levels"] = levels, d["i"] = is, d["j"] = js, d["values"] = values;
            return d;
          },
          py::arg("values_only") = false,
          "The hierarchy as flat arrays (knots, periods, each CV's level, i, j, value); "
          "values_only: the values alone.")
      .def("copy", [](const HSpline& h) { return HSpline(h); })
      .def("with_level", &hsplineWithLevel, py::arg("level"),
           "A copy with a grid on `level`: levels it lacks are made by knot insertion, the "
           "surface unchanged (what an attachment's seam on that level uses).")
      .def_property_readonly("level_count", &HSpline::levelCount)
      .def_property_readonly("cv_count", &HSpline::cvCount)
      .def_property_readonly(
          "closed",
          [](const HSpline& h) { return h.level(0).u.isPeriodic() && h.level(0).v.isPeriodic(); })
      .def_property_readonly("periodic",
                             [](const HSpline& h) {
                               return std::make_pair(h.level(0).u.isPeriodic(),
                                                     h.level(0).v.isPeriodic());
                             })
      .def_property_readonly("domain",
                             [](const HSpline& h) {
                               const HsLevel& l = h.level(0);
                               return std::make_pair(std::make_pair(l.u.lo(), l.u.hi()),
                                                     std::make_pair(l.v.lo(), l.v.hi()));
                             })
      .def(
          "grid_size",
          [](const HSpline& h, int level) {
            if (level < 0 || level >= h.levelCount())
              throw ModelError("hspline: there is no level " + std::to_string(level));
            return std::make_pair(h.level(level).u.count(), h.level(level).v.count());
          },
          py::arg("level"))
      .def(
          "cvs",
          [](const HSpline& h, int level) {
            std::vector<CvTuple> out;
            if (level >= 0 && level < h.levelCount())
              for (const HsCv& cv : h.level(level).cvs) out.emplace_back(level, cv.i, cv.j);
            return out;
          },
          py::arg("level"), "The level's CVs (level, i, j), sorted by (j, i).")
      .def(
          "values",
          [](const HSpline& h, int level) {
            std::vector<Vec3> out;
            for (const HsCv& cv : h.level(level).cvs) out.push_back(cv.value);
            return out;
          },
          py::arg("level"),
          "Level 0: positions; finer levels: offsets (u tangent, v tangent, normal).")
      .def("value",
           [](const HSpline& h, int level, int i, int j) {
             const HsCv* cv = h.find(level, i, j);
             if (!cv) throw ModelError("hspline: there is no " + hsCvName(level, i, j));
             return cv->value;
           })
      .def("positions", &HSpline::positions, py::arg("level"),
           "The level's CV positions in space (cvs() order).")
      .def("position", &HSpline::position, py::arg("level"), py::arg("i"), py::arg("j"))
      .def("has_cv",
           [](const HSpline& h, int level, int i, int j) { return h.find(level, i, j) != nullptr; })
      .def("movable", &HSpline::movable, py::arg("level"), py::arg("i"), py::arg("j"))
      .def("reference", &HSpline::referenceParameter, py::arg("level"), py::arg("i"), py::arg("j"),
           "The (u, v) where the CV's frame sits on its parent.")
      .def(
          "evaluate",
          [](const HSpline& h, double u, double v, int level) {
            return pointDict(h.evaluate(u, v, level));
          },
          py::arg("u"), py::arg("v"), py::arg("level") = -1,
          "dict(point, normal, du, dv) of the levels up to `level` (all by default).")
      .def(
          "refine", &HSpline::refine, py::arg("level"), py::arg("cvs"),
          "Refines around the given (i, j) of the level: the next level gets 7 x 7 CVs about each.")
      .def(
          "refine_selection",
          [](HSpline& h, const std::vector<CvTuple>& cvs) { refineSelection(h, refs(cvs)); },
          py::arg("cvs"))
      .def("move_cv", &HSpline::moveCv, py::arg("level"), py::arg("i"), py::arg("j"),
           py::arg("point"),
           "Moves a CV to a point in space; a fixed CV refuses (ValueError says why).")
      .def("set_value", &HSpline::setValue, py::arg("level"), py::arg("i"), py::arg("j"),
           py::arg("value"))
      .def(
          "zero_offsets",
          [](HSpline& h, const std::vector<CvTuple>& cvs) { h.zeroOffsets(refs(cvs)); },
          py::arg("cvs"))
      .def("unrefine", &HSpline::unrefine,
           "Removes unused zero-offset CVs and empty levels; returns how many CVs went.")
      .def(
          "select_level", [](const HSpline& h, int l) { return tuples(selectLevel(h, l)); },
          py::arg("level"))
      .def(
          "select_region",
          [](const HSpline& h, int l, double u0, double u1, double v0, double v1) {
            return tuples(selectRegion(h, l, u0, u1, v0, v1));
          },
          py::arg("level"), py::arg("u0"), py::arg("u1"), py::arg("v0"), py::arg("v1"))
      .def(
          "select_movable", [](const HSpline& h, int l) { return tuples(selectMovable(h, l)); },
          py::arg("level"))
      .def(
          "keep_movable",
          [](const HSpline& h, const std::vector<CvTuple>& c) {
            return tuples(keepMovable(h, refs(c)));
          },
          py::arg("cvs"))
      .def(
          "select_along_u",
          [](const HSpline& h, const std::vector<CvTuple>& c) {
            return tuples(selectAlongU(h, refs(c)));
          },
          py::arg("cvs"))
      .def(
          "select_along_v",
          [](const HSpline& h, const std::vector<CvTuple>& c) {
            return tuples(selectAlongV(h, refs(c)));
          },
          py::arg("cvs"))
      .def(
          "select_neighbours",
          [](const HSpline& h, const std::vector<CvTuple>& c) {
            return tuples(selectNeighbours(h, refs(c)));
          },
          py::arg("cvs"))
      .def(
          "select_non_zero",
          [](const HSpline& h, int l) { return tuples(selectNonZeroOffsets(h, l)); },
          py::arg("level") = -1)
      .def(
          "bspline",
          [](const HSpline& h) {
            const FlatBSpline f = flatten(h);
            const OccStyleAxis u = occStyle(f.u), v = occStyle(f.v);
            std::vector<std::vector<Vec3>> poles(static_cast<std::size_t>(f.u.count()));
            for (int i = 0; i < f.u.count(); ++i)
              for (int j = 0; j < f.v.count(); ++j)
                poles[i].push_back(f.pole(ourPole(f.u, i), ourPole(f.v, j)));
            py::dict d;
            d["poles"] = poles, d["uknots"] = u.knots, d["umults"] = u.mults, d["vknots"] = v.knots,
            d["vmults"] = v.mults, d["uperiodic"] = u.periodic, d["vperiodic"] = v.periodic;
            return d;
          },
          "The hierarchy as one exact B-spline, the way Part.BSplineSurface."
          "buildFromPolesMultsKnots takes it: poles[i][j], distinct knots and multiplicities.")
      .def(
          "tessellate",
          [](const HSpline& h, double tolerance) {
            py::gil_scoped_release release;
            return tessellate(flatten(h), tolerance).mesh;
          },
          py::arg("tolerance"),
          "A triangle mesh within about `tolerance` of the surface (closed for a torus).")
      .def(
          "tessellation",
          [](const HSpline& h, double tolerance, int level) {
            HsTessellation t;
            {
              py::gil_scoped_release release;
              t = tessellate(flatten(h, level), tolerance);
            }
            // Points and unit normals as tuples, for Coin (frepcore.Mesh carries no normals).
            std::vector<std::tuple<float, float, float>> points, normals;
            for (std::size_t k = 0; k < t.mesh.positions.size(); ++k) {
              const auto& p = t.mesh.positions[k];
              const auto& n = t.mesh.normals[k];
              points.emplace_back(p[0], p[1], p[2]);
              normals.emplace_back(n[0], n[1], n[2]);
            }
            py::dict d;
            d["mesh"] = t.mesh, d["us"] = t.us, d["vs"] = t.vs, d["points"] = points,
            d["normals"] = normals;
            return d;
          },
          py::arg("tolerance"), py::arg("level") = -1,
          "dict(mesh, us, vs, points, normals): the tessellation of the levels up to `level` (all "
          "by default), its sample parameters (vertex i + len(us) * j lies at us[i], vs[j]) and "
          "its points and unit normals, for a display that moves the same vertices while a CV "
          "is dragged.")
      .def(
          "reach_runs",
          [](const HSpline& h, const std::vector<double>& us, const std::vector<double>& vs,
             int level, int i, int j) {
            const HsRegion r = h.reach(level, i, j);
            std::vector<std::pair<std::size_t, std::size_t>> runs;  // (first vertex, count)
            for (std::size_t b = 0; b < vs.size(); ++b)
              for (std::size_t a = 0; a < us.size(); ++a) {
                if (!h.contains(r, us[a], vs[b])) continue;
                const std::size_t at = a + us.size() * b;
                if (!runs.empty() && runs.back().first + runs.back().second == at)
                  ++runs.back().second;
                else
                  runs.push_back({at, 1});
              }
            return runs;
          },
          py::arg("us"), py::arg("vs"), py::arg("level"), py::arg("i"), py::arg("j"),
          "The runs (first vertex, count) of a tessellation grid (vertex a + len(us) * b) that "
          "a change of the CV can move: what a drag's preview re-evaluates.")
      .def(
          "points_in_runs",
          [](const HSpline& h, const std::vector<double>& us, const std::vector<double>& vs,
             const std::vector<std::pair<std::size_t, std::size_t>>& runs) {
            using P = std::tuple<float, float, float>;
            std::vector<std::pair<std::vector<P>, std::vector<P>>> out(runs.size());
            {
              py::gil_scoped_release release;
              const std::vector<HsSurfacePoint> points = h.evaluateGrid(us, vs, runs);
              std::size_t k = 0;
              for (std::size_t r = 0; r < runs.size(); ++r)
                for (std::size_t n = 0; n < runs[r].second && k < points.size(); ++n, ++k) {
                  const HsSurfacePoint& p = points[k];
                  const Vec3 u = p.normal();
                  out[r].first.emplace_back(float(p.position[0]), float(p.position[1]),
                                            float(p.position[2]));
                  out[r].second.emplace_back(float(u[0]), float(u[1]), float(u[2]));
                }
            }
            return out;
          },
          py::arg("us"), py::arg("vs"), py::arg("runs"),
          "(points, normals) of each run's vertices.")
      .def(
          "brep_binary",
          [](const HSpline& h, bool solid) {
            std::string data;
            {
              py::gil_scoped_release release;
              data = hsBrepBinary(h, solid);
            }
            return py::bytes(data);
          },
          py::arg("solid") = true,
          "OpenCASCADE binary BRep of the exact face (a solid when closed and `solid`) with our "
          "tessellation attached as its triangulation, for Part.Shape.importBinary: FreeCAD's "
          "view then draws it without meshing the face again.")
      .def("to_text", &hsText, py::arg("optimised") = false, "The .hs file's text.")
      .def(
          "write_hs",
          [](const HSpline& h, const FilePath& path, bool optimised) {
            writeHsFile(h, path, optimised);
          },
          py::arg("path"), py::arg("optimised") = false)
      .def(
          "write_step",
          [](const HSpline& h, const FilePath& path) { return summaryDict(writeHsStep(h, path)); },
          py::arg("path"),
          "STEP through OpenCASCADE: a solid when closed, else a face; returns a summary dict.");
  m.def(
      "attach_cylinder",
      [](const HSpline& parent, int i0, int i1, int j0, int j1, const HSpline& cylinder,
         int subdivisions, bool closeEnd, int parentLevel) {
        HsAttachment a;
        {
          py::gil_scoped_release release;
          a = attachCylinder(parent, i0, i1, j0, j1, cylinder, subdivisions, closeEnd, parentLevel);
        }
        py::dict d;
        d["mesh"] = a.mesh, d["extraordinary"] = a.extraordinary,
        d["boundary_loops"] = a.boundaryLoops;
        d["control_faces"] = a.controlFaces;
        return d;
      },
      py::arg("parent"), py::arg("i0"), py::arg("i1"), py::arg("j0"), py::arg("j1"),
      py::arg("cylinder"), py::arg("subdivisions") = 3, py::arg("close_end") = false,
      py::arg("parent_level") = 0,
      "Seed 003's attachment: the cylinder's next-to-last row of CVs joined to the ring of "
      "parent CVs around [i0, i1] x [j0, j1] (cylinder CV k over ring CV k, the ring running "
      "+i, +j, -i, -j from (i0, j0)); the joined net as a Catmull-Clark surface subdivided "
      "`subdivisions` times; close_end closes the cylinder's free end with one face; "
      "parent_level takes the ring and the parent's net on that level (the seam refined: twice "
      "the CVs around per level, the parent's detail up to it kept; rectangle indices on it). "
      "dict(mesh, extraordinary, boundary_loops, control_faces).");
  m.def(
      "envelope",
      [](const HSpline& rest, const std::vector<std::tuple<Vec3, Vec3, Mat34>>& segments,
         const std::vector<int>& levels, double jointReach, bool refineJoints) {
        std::vector<HsSegment> bones;
        for (const auto& [start, end, motion] : segments) bones.push_back({start, end, motion});
        HsEnvelopeSettings settings;
        settings.levels = levels, settings.jointReach = jointReach;
        settings.refineJoints = refineJoints;
        HsEnvelope e;
        {
          py::gil_scoped_release release;
          e = envelope(rest, bones, settings);
        }
        py::dict d;
        d["hspline"] = e.surface, d["bound_per_segment"] = e.boundPerSegment;
        d["bound_per_level"] = e.boundPerLevel, d["blended"] = e.blended;
        d["joints"] = e.joints, d["joint_reach"] = e.jointReach;
        return d;
      },
      py::arg("rest"), py::arg("segments"), py::arg("levels") = std::vector<int>{0, 1},
      py::arg("joint_reach") = 0.0, py::arg("refine_joints") = true,
      "Seed 003's enveloping: the CVs of `levels` bound to skeleton segments, each given as "
      "(rest start, rest end, motion), the motion a rigid 3x4 row-major matrix from the rest "
      "pose to the current one. Level 0 goes with each CV's nearest segment; finer levels "
      "blend the rotations of a joint's two segments within joint_reach of it (0: sized from "
      "the control net); refine_joints refines level 0 there first. dict(hspline, "
      "bound_per_segment, bound_per_level, blended, joints, joint_reach).");
  m.def(
      "hspline_shell_lattice",
      [](const HSpline& h, double thickness, double cell, const std::string& cellType,
         double radius, std::pair<int, int> divisions, const std::string& source, bool straight) {
        HsplineShellSettings settings;
        settings.straight = straight;
        settings.thickness = thickness, settings.cell = cell, settings.cellType = cellType;
        settings.radius = radius;
        settings.divisionsU = divisions.first, settings.divisionsV = divisions.second;
        HsplineShell shell;
        {
          py::gil_scoped_release release;
          shell = hsplineShellLattice(h, settings, source);
        }
        py::dict d;
        d["model"] = modelToJson(shell.model), d["size"] = shell.size, d["cells"] = shell.cells;
        d["divisions"] = py::make_tuple(shell.divisions[0], shell.divisions[1]);
        d["deviation"] = shell.deviation;
        return d;
      },
      py::arg("hspline"), py::arg("thickness"), py::arg("cell") = 0.0,
      py::arg("cell_type") = "octet", py::arg("radius") = 0.0,
      py::arg("divisions") = std::pair<int, int>{0, 0}, py::arg("source") = "the hspline",
      py::arg("straight") = false,
      "A strut lattice in a shell `thickness` thick along the hspline, its cells following the "
      "surface's parameters through an FFD lattice fitted to it (`frepcad hspline lattice`; "
      "cell 0: half the thickness, radius 0: a tenth of a cell, divisions 0: level 0's CVs "
      "less one; straight: each strut straight between its ends' images, not curved with the "
      "surface). dict(model (JSON text), size, cells, divisions, deviation: how closely the "
      "lattice follows the surface).");
  m.def("parse_hs", &parseHs, py::arg("text"), py::arg("source") = "<text>");
  m.def(
      "read_hs", [](const FilePath& path) { return readHsFile(path); }, py::arg("path"));
  m.def(
      "read_step_summary", [](const FilePath& path) { return summaryDict(readStepSummary(path)); },
      py::arg("path"),
      "What OpenCASCADE reads from a STEP file: solids, shells, faces, valid, volume, area.");
}

}  // namespace frep

// frepcore's trees: the Node class (evaluation, bounds, meshing, export, brick jobs) and the
// model and volume sources (parse_model, mesh_field, vdb_grids, vdb_to_mesh).
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

#include "base/atomic_file.h"
#include "base/errors.h"
#include "base/exit_status.h"
#include "base/process_memory.h"
#include "base/progress.h"
#include "base/triangle_geometry.h"
#include "check/mesh_check.h"
#include "check/mesh_deviation.h"
#include "check/printability.h"
#include "frep/bounds.h"
#include "frep/hyperfun_import.h"
#include "frep/model_json.h"
#include "frep/registry.h"
#include "frep/registry_docs.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"
#include "io/mesh_3mf.h"
#include "io/mesh_io.h"
#include "io/mesh_piece_file.h"
#include "lattice/ffd_lattice.h"
#include "lattice/lattice_file.h"
#include "mesh/mesh_ffd.h"
#include "mesh/mesher.h"
#include "mesh/section.h"
#include "pipeline/beam_export.h"
#include "pipeline/brick_jobs.h"
#include "pipeline/export_pipeline.h"
#include "python/binding_helpers.h"
#include "python/bindings.h"
#include "repair/repair.h"
#include "simplify/straighten_creases.h"
#include "volume/field_sources.h"
#include "volume/grid_ffd.h"
#include "volume/grid_set.h"
#include "volume/level_sets.h"

namespace frep {

void bindNode(py::module_& m) {
  py::class_<PyNode>(m, "Node", "An immutable, validated FRep tree node.")
      .def(py::init(&makePyNode), py::arg("type"), py::arg("params") = py::dict(),
           py::arg("inputs") = std::vector<PyNode>{}, py::arg("path") = "node",
           "Makes a node; raises ValueError naming the path, the parameter and what is allowed.")
      .def_property_readonly("type", [](const PyNode& n) { return n.node->type->id; })
      .def_property_readonly("params", &nodeParams)
      .def_property_readonly("inputs",
                             [](const PyNode& n) {
                               std::vector<PyNode> out;
                               for (const auto& i : n.node->inputs)
                                 out.push_back(PyNode{i, nullptr});
                               return out;
                             })
      .def(
          "value",
          [](PyNode& n, double x, double y, double z) { return n.compiled().eval(x, y, z); },
          py::arg("x"), py::arg("y"), py::arg("z"), "F(x, y, z): >= 0 inside.")
      .def(
          "values",
          [](PyNode& n, const std::vector<Vec3>& points) {
            const Program& p = n.compiled();
            std::vector<double> x(points.size()), y(points.size()), z(points.size()),
                out(points.size());
            for (std::size_t i = 0; i < points.size(); ++i) {
              x[i] = points[i][0];
              y[i] = points[i][1];
              z[i] = points[i][2];
            }
            py::gil_scoped_release release;
            p.evalBatch(x.data(), y.data(), z.data(), points.size(), out.data());
            return out;
          },
          py::arg("points"))
      .def(
          "gradient",
          [](PyNode& n, double x, double y, double z) {
            Dual d = n.compiled().evalGradient(x, y, z);
            return py::make_tuple(d.v, py::make_tuple(d.d[0], d.d[1], d.d[2]));
          },
          "(F, (dF/dx, dF/dy, dF/dz)) at a point.")
      .def(
          "interval",
          [](PyNode& n, const Vec3& lo, const Vec3& hi) {
            Interval v = n.compiled().evalInterval(Interval(lo[0], hi[0]), Interval(lo[1], hi[1]),
                                                   Interval(lo[2], hi[2]));
            return py::make_tuple(v.lo, v.hi);
          },
          "Bounds of F over the box [lo, hi].")
      .def(
          "bounds",
          [](PyNode& n, double search, double tolerance) {
            BoundsOptions o;
            o.search = Box3{{-search, -search, -search}, {search, search, search}};
            o.tolerance = tolerance;
            o.known = structuralBounds(n.node);
            const Program& p = n.compiled();
            SolidBounds b;
            {
              py::gil_scoped_release release;
              b = findBounds(p, o);
            }
            return boundsDict(b);
          },
          py::arg("search") = 1e6, py::arg("tolerance") = 1e-4,
          "Tight box of the solid by interval branch and bound: dict(empty, bounded, "
          "unbounded_sides, box).")
      .def("instruction_count", [](PyNode& n) { return n.compiled().instructionCount(); })
      .def(
          "choose_box",
          [](PyNode& n, py::object bbox, py::object resolution, py::object cells,
             double paddingCells, py::object bounds) {
            const BoxRequest r = boxRequest(bbox, resolution, cells, paddingCells);
            MeshingBox m;
            if (!bounds.is_none()) {
              m = chooseBox(boundsFromDict(bounds.cast<py::dict>()), r);
            } else {
              const Program& p = n.compiled();
              const Box3 known = structuralBounds(n.node);
              py::gil_scoped_release release;
              m = chooseBox(p, known, r);
            }
            return py::make_tuple(fromBox(m.box), m.resolution);
          },
          py::arg("bbox") = py::none(), py::arg("resolution") = py::none(),
          py::arg("cells") = py::none(), py::arg("padding_cells") = kPaddingCells,
          py::arg("bounds") = py::none(),
          "The export pipeline's box policy: ((lo, hi), cell size).")
      .def(
          "export",
          [](PyNode& n, const FilePath& path, py::object bbox, py::object resolution,
             py::object cells, const std::string& format, bool check, bool force,
             py::object progress, const MeshSettings& settings) {
            ExportRequest r;
            r.mesh = settings;
            r.box = boxRequest(bbox, resolution, cells, kPaddingCells);
            r.known = structuralBounds(n.node);
            if (!format.empty()) r.format = parseFormat(format);
            r.check = check;
            r.force = force;
            n.compiled();
            std::shared_ptr<const Program> program = n.program;
            // Stages as one bar for Python's progress: bounds 2 %, meshing 38 %, checking
            // 55 %, writing the rest.
            ExportResult result = runWithProgress<ExportResult>(
                [&](std::function<bool(double)> tick) {
                  r.progress = stagesAsPhases(tick, {0.02, 0.38, 0.55, 0.05});
                  return exportField(*program, r, path, path);
                },
                progress);
            py::dict d = exportResultDict(result, path);
            if (result.simplified) {
              d["triangles_before_simplify"] = result.simplify.trianglesBefore;
              d["largest_distance"] = result.simplify.largestDistance;
            }
            if (result.straightened)
              d["straightened"] = py::dict(py::arg("merged") = result.straighten.collapses,
                                           py::arg("flipped") = result.straighten.flips,
                                           py::arg("seconds") = result.straighten.seconds);
            return d;
          },
          py::arg("path"), py::arg("bbox") = py::none(), py::arg("resolution") = py::none(),
          py::arg("cells") = py::none(), py::arg("format") = "", py::arg("check") = true,
          py::arg("force") = false, py::arg("progress") = py::none(),
          py::arg("settings") = MeshSettings(),
          "The export pipeline: box policy, mesh with `settings` (MeshSettings: straightened "
          "creases give 'straightened' in the dict, a tolerance 'triangles_before_simplify' "
          "and 'largest_distance'), CGAL check, atomic write. Returns the check report dict "
          "plus 'written'; a refused mesh is not written unless force.")
      .def(
          "export_beams",
          [](PyNode& n, const FilePath& path, py::object bbox, py::object resolution,
             py::object cells, const std::string& unit, bool force, py::object progress,
             const MeshSettings& settings) {
            const BoxRequest request = boxRequest(bbox, resolution, cells, kPaddingCells);
            ThreeMfOptions o;
            o.unit = parseLengthUnit(unit);
            o.metadata = {{"Application", "FRepCAD frepcore"}};
            n.compiled();
            std::shared_ptr<const Program> program = n.program;
            const NodePtr root = n.node;
            const std::string name = std::filesystem::path(path.value).stem().string();
            BeamExportResult r = runWithProgress<BeamExportResult>(
                [&](std::function<bool(double)> tick) {
                  const MeshingBox box = chooseBox(*program, structuralBounds(root), request);
                  return exportBeamLattice(root, box, settings, o, name, path, force, tick);
                },
                progress);
            py::dict d;
            d["written"] = r.written;
            d["beams"] = r.beams;
            d["vertices"] = r.vertices;
            d["clip_triangles"] = r.clipTriangles;
            d["skin_triangles"] = r.skinTriangles;
            d["clipped"] = r.clipped;
            d["mesh_tolerance"] = r.meshTolerance;
            d["summary"] = beamExportSummary(r);
            d["printable"] = r.clipped ? r.clipReport.printable() : r.skinReport.printable();
            const std::string text =
                r.clipped ? reportToText(r.clipReport, path.value + ": the part's mesh")
                          : reportToText(r.skinReport, path.value + ": the skin");
            d["text"] = text;
            d["notes"] = r.notes;
            d["seconds"] = r.seconds;
            return d;
          },
          py::arg("path"), py::arg("bbox") = py::none(), py::arg("resolution") = py::none(),
          py::arg("cells") = py::none(), py::arg("unit") = "mm", py::arg("force") = false,
          py::arg("progress") = py::none(), py::arg("settings") = MeshSettings(),
          "A strut lattice's struts as a 3MF beam lattice (frepcad export --beams): the shape "
          "must be a strut_lattice or voronoi_foam cut to a part or an infill with a strut "
          "lattice. Returns "
          "dict(written, beams, vertices, clipped, clip_triangles, skin_triangles, "
          "mesh_tolerance (the skin or the part's mesh simplified within it: the settings' "
          "tolerance, else a tenth of a cell; 0: not simplified), printable, summary, text, "
          "notes, seconds); ValueError for another shape.")
      .def(
          "brick_plan",
          [](PyNode& n, py::object bbox, double resolution, std::uint32_t jobs,
             const MeshSettings& settings) {
            const BrickJobPlan plan = brickPlanOf(n, bbox, resolution, jobs, settings);
            py::dict d;
            d["jobs"] = plan.jobs;
            d["bricks"] = py::make_tuple(plan.bricks[0], plan.bricks[1], plan.bricks[2]);
            d["split"] = py::make_tuple(plan.split[0], plan.split[1], plan.split[2]);
            d["run_id"] = plan.runId;
            return d;
          },
          py::arg("bbox"), py::arg("resolution"), py::arg("jobs") = 1,
          py::arg("settings") = MeshSettings(),
          "A brick-job run: the mesher's bricks per axis, the jobs per axis and the run's id. "
          "ValueError for a job count the bricks cannot take, or settings they cannot (a "
          "refinement, straightened creases, a tolerance).")
      .def(
          "brick_job",
          [](PyNode& n, py::object bbox, double resolution, std::uint32_t jobs, std::uint32_t job,
             const FilePath& path, const MeshSettings& settings) {
            const BrickJobPlan plan = brickPlanOf(n, bbox, resolution, jobs, settings);
            const auto start = std::chrono::steady_clock::now();
            MeshPiece piece;
            {
              py::gil_scoped_release release;
              piece = runBrickJob(n.compiled(), plan, job);
              writePieceFile(piece, path);
              // the job judges its own piece for the check too: the merge then reads only
              // the summary (a few per cent of the piece) instead of checking the piece
              const std::vector<char> summary = judgeBrickPiece(plan, piece);
              AtomicFile out(path.value + ".check");
              out.write(summary.data(), summary.size());
              out.commit();
            }
            py::dict d;
            d["job"] = job;
            d["path"] = path;
            d["vertices"] = piece.keys.size();
            d["triangles"] = piece.triangles.size();
            d["seconds"] =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            return d;
          },
          py::arg("bbox"), py::arg("resolution"), py::arg("jobs"), py::arg("job"), py::arg("path"),
          py::arg("settings") = MeshSettings(),
          "Meshes job `job` of the run into a piece file at `path` (written atomically).")
      .def(
          "merge_bricks",
          [](PyNode& n, py::object bbox, double resolution, std::uint32_t jobs,
             const std::vector<std::string>& pieces, const FilePath& path,
             const std::string& format, bool check, bool force, py::object progress,
             const std::string& unit,
             const std::vector<std::pair<std::string, std::string>>& metadata,
             const MeshSettings& settings) {
            const BrickJobPlan plan = brickPlanOf(n, bbox, resolution, jobs, settings);
            ExportRequest r;
            if (!format.empty()) r.format = parseFormat(format);
            if (!unit.empty()) r.threeMf.unit = parseLengthUnit(unit);
            r.threeMf.metadata = metadata;
            r.check = check;
            r.force = force;
            // merging 30 %, checking 65 %, writing the rest
            ExportResult result = runWithProgress<ExportResult>(
                [&](std::function<bool(double)> tick) {
                  r.progress = stagesAsPhases(tick, {0.0, 0.3, 0.65, 0.05});
                  // the jobs' check summaries, where every piece has one
                  std::vector<std::string> summaries;
                  for (const std::string& piece : pieces)
                    if (std::filesystem::exists(piece + ".check"))
                      summaries.push_back(piece + ".check");
                  if (summaries.size() != pieces.size()) summaries.clear();
                  return exportPieces(plan, pieces, r, path, summaries);
                },
                progress);
            return exportResultDict(result, path);
          },
          py::arg("bbox"), py::arg("resolution"), py::arg("jobs"), py::arg("pieces"),
          py::arg("path"), py::arg("format") = "", py::arg("check") = true,
          py::arg("force") = false, py::arg("progress") = py::none(), py::arg("unit") = "",
          py::arg("metadata") = std::vector<std::pair<std::string, std::string>>(),
          py::arg("settings") = MeshSettings(),
          "Welds the run's piece files (one per job, in job order), checks the mesh and "
          "writes `path` atomically (a binary STL or a 3MF streamed, never whole in memory; "
          "unit and metadata for a 3MF): the export's report dict plus 'written'.")
      .def(
          "section",
          [](PyNode& n, const Vec3& origin, const Vec3& u, const Vec3& v, py::object bbox,
             double cell, py::object progress) {
            SectionPlane plane{origin, u, v};
            const Box3 box = toBox(bbox.cast<py::sequence>());
            double u0, u1, v0, v1;
            py::list out;
            if (!sectionRectangle(plane, box, u0, u1, v0, v1)) return out;
            n.compiled();
            std::shared_ptr<const Program> program = n.program;
            const std::vector<SectionLoop> loops = runWithProgress<std::vector<SectionLoop>>(
                [=](std::function<bool(double)> tick) {
                  return sectionField(*program, plane, u0, u1, v0, v1, cell, Progress(tick));
                },
                progress);
            for (const SectionLoop& l : loops) {
              py::list points;
              for (const Vec3& p : l.points) points.append(py::make_tuple(p[0], p[1], p[2]));
              out.append(py::make_tuple(points, l.closed));
            }
            return out;
          },
          py::arg("origin"), py::arg("u"), py::arg("v"), py::arg("bbox"), py::arg("cell"),
          py::arg("progress") = py::none(),
          "The contours where the plane through `origin` spanned by the unit vectors u and v "
          "(at right angles) cuts the solid inside bbox, sampled at `cell`: a list of "
          "(points, closed), the solid on the left of each loop seen against u x v; holes "
          "are loops of their own, turning the other way (mesh/section.h).")
      .def(
          "mesh",
          [](PyNode& n, py::object bbox, double resolution, py::object progress, bool normals,
             const MeshSettings& settings) {
            MeshingOptions o;
            o.settings = settings;
            o.bbox = toBox(bbox.cast<py::sequence>());
            o.resolution = resolution;
            o.normals = normals;
            // A preview too large for the memory is refused with the figures, before any
            // allocation (FreeCAD would die with the process).
            o.memoryBudget = availableMemory();
            n.compiled();
            std::shared_ptr<const Program> program = n.program;
            auto stats = std::make_shared<MeshingStats>();
            auto straightened = std::make_shared<SimplifyStats>();
            py::object mesh = py::cast(runWithProgress<TriangleMesh>(
                [program, o, stats, straightened](std::function<bool(double)> tick) mutable {
                  FinishedMesh m = meshAndFinish(*program, o, tick, false);
                  *stats = std::move(m.stats);
                  *straightened = m.straighten;
                  return std::move(m.mesh);
                },
                progress));
            mesh.attr("thin_parts") = thinPartsDict(*stats);
            if (settings.straightenCreases)
              mesh.attr("straightened") = py::dict(py::arg("merged") = straightened->collapses,
                                                   py::arg("flipped") = straightened->flips,
                                                   py::arg("seconds") = straightened->seconds);
            return mesh;
          },
          py::arg("bbox"), py::arg("resolution"), py::arg("progress") = py::none(),
          py::arg("normals") = false, py::arg("settings") = MeshSettings(),
          "Polygonises inside bbox with cells of at most `resolution` with `settings` "
          "(MeshSettings; with straighten_creases the mesh's straightened says {'merged', "
          "'flipped', 'seconds'}). progress(fraction) is called on this thread; returning "
          "False cancels (raises Cancelled). The mesh's thin_parts says where parts thinner "
          "than a cell passed between the grid's points: {'solid': grid edges of solid left "
          "out, 'gaps': of gaps closed (both with no surface near), 'tips': of crease tips cut "
          "short, 'example': a point on one, 'refined_cubes': the cubes round them meshed "
          "again at half a cell (refine), and with refine_levels > 1 'refined_levels' and "
          "'refined_deeper_cubes': the smaller cubes meshed again below that, down to a "
          "cell / 2^refined_levels}.")
      .def(
          "to_vdb",
          [](PyNode& n, const FilePath& path, py::object bbox, double voxel, double halfWidth,
             py::object progress, bool fog) {
            LevelSetOptions o;
            o.voxel = voxel;
            o.halfWidthVoxels = halfWidth;
            o.fog = fog;
            const Box3 box = toBox(bbox.cast<py::sequence>());
            n.compiled();
            std::shared_ptr<const Program> program = n.program;
            const GridSet grids = runWithProgress<GridSet>(
                [&](std::function<bool(double)> tick) {
                  o.progress = tick;
                  GridSet g = sampleLevelSet(*program, box, o);
                  writeVdb(g, path);
                  return g;
                },
                progress);
            return gridInfoDict(grids.info(0));
          },
          py::arg("path"), py::arg("bbox"), py::arg("voxel"), py::arg("half_width") = 3.0,
          py::arg("progress") = py::none(), py::arg("fog") = false,
          "Samples the solid inside bbox into an OpenVDB level set (voxel size `voxel`, narrow "
          "band of half_width voxels each side) and writes it to path atomically; returns the "
          "grid's description (vdb_grids' dict). fog=True: a fog volume instead (0 outside, 1 "
          "inside, a ramp across the band inside).")
      .def(
          "to_json",
          [](const PyNode& n, py::object bbox, py::object resolution,
             const std::string& description) {
            Model model;
            model.root = n.node;
            if (!bbox.is_none()) model.bbox = toBox(bbox.cast<py::sequence>());
            if (!resolution.is_none()) model.resolution = resolution.cast<double>();
            model.description = description;
            return modelToJson(model);
          },
          py::arg("bbox") = py::none(), py::arg("resolution") = py::none(),
          py::arg("description") = "");

  m.def(
      "parse_model",
      [](const std::string& text, const std::string& source, const FilePath& folder) {
        Model model = parseModel(text, source, folder);
        py::dict d;
        d["root"] = PyNode{model.root, nullptr};
        d["bbox"] = model.bbox ? py::object(fromBox(*model.bbox)) : py::object(py::none());
        d["resolution"] =
            model.resolution ? py::object(py::float_(*model.resolution)) : py::object(py::none());
        d["description"] = model.description;
        return d;
      },
      py::arg("text"), py::arg("source") = "model", py::arg("base_directory") = "",
      "Parses a JSON model: dict(root, bbox, resolution, description). Relative file names "
      "(mesh_sdf, vdb_grid) are read from base_directory when given.");
  m.def(
      "parse_hyperfun",
      [](const std::string& text, const std::string& source) {
        Model model = importHyperFun(text, source);
        py::dict d;
        d["root"] = PyNode{model.root, nullptr};
        d["bbox"] = py::none();
        d["resolution"] = py::none();
        d["description"] = model.description;
        // the features' names, by the JSON of each node's tree (Node.to_json())
        py::dict labels;
        for (const auto& [node, label] : model.labels) {
          Model one;
          one.root = NodePtr(model.root, node);  // (aliasing: alive while the tree is)
          labels[py::str(modelToJson(one))] = label;
        }
        d["labels"] = labels;
        return d;
      },
      py::arg("text"), py::arg("source") = "model.hf",
      "Translates a HyperFun program (.hf) into a model: dict(root, bbox, resolution, "
      "description) as parse_model gives, and labels: {node.to_json(): the program's name "
      "for it}. Each library primitive is a formula node with "
      "HyperFun's own expression, | & \\ ~ and the blends are set-operation and blend nodes "
      "with alpha 0 (docs/hyperfun.md). Raises ValueError naming the line and column.");

  m.def(
      "mesh_field",
      [](const TriangleMesh& mesh, const std::string& method, double voxel,
         const std::string& name) {
        if (method != "exact" && method != "grid")
          throw ModelError(name + ": method '" + method + "' is not allowed; allowed: exact, grid");
        std::shared_ptr<const Field> f;
        {
          py::gil_scoped_release release;
          f = meshField(mesh, method == "grid" ? MeshFieldMethod::Grid : MeshFieldMethod::Exact,
                        voxel, name);
        }
        return PyNode{makeFieldNode(f, name), nullptr};
      },
      py::arg("mesh"), py::arg("method") = "exact", py::arg("voxel") = 0.0,
      py::arg("name") = "mesh",
      "A closed mesh in memory as a solid (a tree leaf that no model file can hold): its exact "
      "signed distance, or an OpenVDB level set at `voxel` (0: 1/256 of its largest side). "
      "Raises OSError naming `name` for an open, non-manifold or (exact) self-intersecting mesh.");
  m.def(
      "vdb_grids",
      [](const FilePath& path) {
        GridSet grids;
        {
          py::gil_scoped_release release;
          grids = readVdb(path);
        }
        py::list out;
        for (std::size_t i = 0; i < grids.size(); ++i) out.append(gridInfoDict(grids.info(i)));
        return out;
      },
      py::arg("path"),
      "The grids of a .vdb file: dicts of name, value_type, grid_class, voxel_size, "
      "active_voxels, box (world, of the active voxels), metadata, text.");
  m.def(
      "vdb_to_mesh",
      [](const FilePath& path, const std::string& grid, double iso, double adaptivity) {
        py::gil_scoped_release release;
        const GridSet grids = readVdb(path);
        return levelSetToMesh(grids, grids.scalarGrid(grid, path), iso, adaptivity);
      },
      py::arg("path"), py::arg("grid") = "", py::arg("iso") = 0.0, py::arg("adaptivity") = 0.0,
      "OpenVDB's volumeToMesh of a grid of a .vdb file (the first float or double grid when "
      "`grid` is empty), outward-oriented; judge it with Mesh.check() before printing.");
}

}  // namespace frep

// _frepcore: the thin pybind11 layer over libcore. It converts Python values to libcore types
// and back, releases the GIL for long work, and runs that work on a worker thread so that the
// Python progress callback is always called on the caller's thread (FreeCAD's progress bar and
// its cancel live in the GUI thread). The pythonic modelling API is in frepcore/__init__.py.
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/global_control.h>

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
#include "base/process_memory.h"
#include "base/triangle_geometry.h"
#include "check/mesh_check.h"
#include "check/mesh_deviation.h"
#include "check/printability.h"
#include "frep/bounds.h"
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
#include "pipeline/brick_jobs.h"
#include "pipeline/export_pipeline.h"
#include "python/bindings.h"
#include "repair/repair.h"
#include "simplify/straighten_creases.h"
#include "volume/field_sources.h"
#include "volume/grid_ffd.h"
#include "volume/grid_set.h"
#include "volume/level_sets.h"

namespace py = pybind11;

namespace frep {
namespace {

// ---- values -------------------------------------------------------------------------------

ParamValue toParamValue(const ParamTemplate& t, const py::handle& v, const std::string& where) {
  ParamValue out;
  auto fail = [&](const std::string& what) {
    throw ModelError(where + ": parameter '" + t.name + "' " + what +
                     "; allowed: " + t.rangeText());
  };
  if (t.type == ParamType::Choice || t.type == ParamType::Text) {
    if (!py::isinstance<py::str>(v)) fail("must be text");
    out.text = v.cast<std::string>();
    return out;
  }
  if (t.type == ParamType::Points) {
    if (py::isinstance<py::str>(v) || !py::isinstance<py::sequence>(v))
      fail("must be a sequence of points (x, y, z)");
    for (auto q : v.cast<py::sequence>()) {
      if (py::isinstance<py::str>(q) || !py::isinstance<py::sequence>(q) ||
          py::len(q) != 3)
        fail("must be a sequence of points (x, y, z)");
      try {
        for (auto c : q.cast<py::sequence>()) out.numbers.push_back(c.cast<double>());
      } catch (const py::cast_error&) {
        fail("must be a sequence of points (x, y, z) of numbers");
      }
    }
    return out;
  }
  std::size_t expected = t.type == ParamType::Vector3 ? 3 : t.type == ParamType::Matrix3x4 ? 12 : 1;
  if (expected == 1) {
    if (py::isinstance<py::str>(v) || py::isinstance<py::sequence>(v)) fail("must be a number");
    try {
      out.numbers = {v.cast<double>()};
    } catch (const py::cast_error&) {
      fail("must be a number");
    }
    return out;
  }
  if (py::isinstance<py::str>(v) || !py::isinstance<py::sequence>(v))
    fail("must be a sequence of " + std::to_string(expected) + " numbers");
  auto seq = v.cast<py::sequence>();
  if (seq.size() != expected)
    fail("has " + std::to_string(seq.size()) + " values, needs " + std::to_string(expected));
  for (auto item : seq) {
    try {
      out.numbers.push_back(item.cast<double>());
    } catch (const py::cast_error&) {
      fail("must be a sequence of " + std::to_string(expected) + " numbers");
    }
  }
  return out;
}

py::object fromParamValue(const ParamTemplate& t, const ParamValue& v) {
  switch (t.type) {
    case ParamType::Choice:
    case ParamType::Text:
      return py::str(v.text);
    case ParamType::Boolean:
      return py::bool_(v.numbers.at(0) != 0.0);
    case ParamType::Integer:
      return py::int_(static_cast<long long>(v.numbers.at(0)));
    case ParamType::Real:
      return py::float_(v.numbers.at(0));
    case ParamType::Points: {
      py::list points;
      for (const Vec3& q : pointsOf(v)) points.append(py::make_tuple(q[0], q[1], q[2]));
      return py::tuple(points);
    }
    default:
      return py::tuple(py::cast(v.numbers));
  }
}

// 'cubes' (the default) or 'tetra'; anything else is a ValueError naming the argument.
Extraction parseMesher(const std::string& name) {
  if (name == "cubes") return Extraction::Cubes;
  if (name == "tetra") return Extraction::Tetrahedra;
  throw py::value_error("mesher must be 'cubes' or 'tetra', got '" + name + "'");
}

Box3 toBox(const py::sequence& s) {
  if (s.size() == 6) {
    Box3 b;
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = s[a].cast<double>();
      b.hi[a] = s[a + 3].cast<double>();
    }
    return b;
  }
  if (s.size() == 2) {
    auto lo = s[0].cast<Vec3>(), hi = s[1].cast<Vec3>();
    return Box3{lo, hi};
  }
  throw ModelError("bounding box: needs (xmin, ymin, zmin, xmax, ymax, zmax) or (min, max)");
}

py::tuple fromBox(const Box3& b) {
  return py::make_tuple(py::cast(b.lo), py::cast(b.hi));
}

// ---- long work with progress --------------------------------------------------------------

// Runs work(progress) on a worker thread with the GIL released. The Python callback
// `progress(fraction) -> bool|None` is polled on this thread every 50 ms; False (or an
// exception in it) cancels the work at its next progress report.
template <class Result, class Work>
Result runWithProgress(Work work, const py::object& progress) {
  std::atomic<double> fraction{0.0};
  std::atomic<bool> cancel{false};
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  Result result{};
  std::exception_ptr workError, callbackError;
  {
    py::gil_scoped_release release;
    std::thread worker([&] {
      try {
        result = work([&](double f) {
          fraction = f;
          return !cancel.load();
        });
      } catch (...) {
        workError = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(m);
      done = true;
      cv.notify_all();
    });
    std::unique_lock<std::mutex> lock(m);
    while (!cv.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; })) {
      if (progress.is_none() || cancel) continue;
      lock.unlock();
      {
        py::gil_scoped_acquire acquire;
        try {
          py::object keep = progress(fraction.load());
          if (!keep.is_none() && !keep.cast<bool>()) cancel = true;
        } catch (...) {
          callbackError = std::current_exception();
          cancel = true;
        }
      }
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (callbackError) std::rethrow_exception(callbackError);
  if (workError) std::rethrow_exception(workError);
  // Work that does not report progress (the CGAL check) runs to its end; a cancel asked for
  // meanwhile still holds, so the caller does not go on to write a file.
  if (cancel) throw Cancelled();
  if (!progress.is_none()) progress(1.0);
  return result;
}

// An export's progress by stage as one fraction: stage s runs from ends[s] to ends[s + 1].
std::function<bool(ExportStage, double)> stagesAsOneFraction(
    const std::function<bool(double)>& tick, const std::array<double, 5>& ends) {
  return [tick, ends](ExportStage s, double f) {
    const int i = static_cast<int>(s);
    return tick(ends[i] + (ends[i + 1] - ends[i]) * f);
  };
}


// ---- wrapped types --------------------------------------------------------------------------

struct PyNode {
  NodePtr node;
  std::shared_ptr<const Program> program;  // compiled on first use

  const Program& compiled() {
    if (!program) program = std::make_shared<const Program>(compile(node));
    return *program;
  }
};

PyNode makePyNode(const std::string& typeId, const py::dict& params,
                  const std::vector<PyNode>& inputs, const std::string& path) {
  const NodeType& type = registry().get(typeId);
  std::map<std::string, ParamValue> values;
  for (auto item : params) {
    const std::string name = item.first.cast<std::string>();
    const ParamTemplate* t = type.findParam(name);
    if (!t) throw ModelError(path + " (" + typeId + "): " + type.unknownParamText(name));
    values[name] = toParamValue(*t, item.second, path + " (" + typeId + ")");
  }
  std::vector<NodePtr> in;
  for (const auto& p : inputs) in.push_back(p.node);
  return PyNode{makeNode(typeId, std::move(values), std::move(in), path), nullptr};
}

// A brick-job run of this solid (pipeline/brick_jobs.h); the run's id fingerprints the
// tree's canonical JSON, so the driver and every worker agree on it.
BrickJobPlan brickPlanOf(PyNode& n, const py::object& bbox, double resolution, bool sharp,
                         const std::string& mesher, std::uint32_t jobs, bool fewerTriangles) {
  MeshingBox box{toBox(bbox.cast<py::sequence>()), resolution};
  Model model;
  model.root = n.node;
  return planBrickJobs(box, sharp, parseMesher(mesher), jobs, textFingerprint(modelToJson(model)),
                       fewerTriangles);
}

py::dict nodeParams(const PyNode& n) {
  py::dict d;
  for (const auto& p : n.node->type->params)
    d[p.name.c_str()] = fromParamValue(p, n.node->param(p.name));
  return d;
}

py::dict boundsDict(const SolidBounds& b) {
  py::dict d;
  d["empty"] = b.empty;
  d["bounded"] = b.bounded();
  py::list sides;
  const char* names[3][2] = {{"-x", "+x"}, {"-y", "+y"}, {"-z", "+z"}};
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s)
      if (b.unbounded[a][s]) sides.append(names[a][s]);
  d["unbounded_sides"] = sides;
  d["box"] = b.empty ? py::object(py::none()) : py::object(fromBox(b.box));
  return d;
}

SolidBounds boundsFromDict(const py::dict& d) {
  SolidBounds b;
  b.empty = d["empty"].cast<bool>();
  const char* names[3][2] = {{"-x", "+x"}, {"-y", "+y"}, {"-z", "+z"}};
  for (auto side : d["unbounded_sides"].cast<py::list>()) {
    const std::string n = side.cast<std::string>();
    for (int a = 0; a < 3; ++a)
      for (int s = 0; s < 2; ++s)
        if (n == names[a][s]) b.unbounded[a][s] = true;
  }
  if (!b.empty) b.box = toBox(d["box"].cast<py::sequence>());
  return b;
}

BoxRequest boxRequest(const py::object& bbox, const py::object& resolution,
                      const py::object& cells, double paddingCells) {
  BoxRequest r;
  if (!bbox.is_none()) r.bbox = toBox(bbox.cast<py::sequence>());
  if (!resolution.is_none()) r.resolution = resolution.cast<double>();
  if (!cells.is_none()) r.cells = cells.cast<int>();
  r.paddingCells = paddingCells;
  return r;
}

py::dict gridInfoDict(const GridInfo& g) {
  py::dict d;
  d["name"] = g.name;
  d["value_type"] = g.valueType;
  d["grid_class"] = g.gridClass;
  d["voxel_size"] = py::make_tuple(g.voxelSize[0], g.voxelSize[1], g.voxelSize[2]);
  d["active_voxels"] = g.activeVoxels;
  d["box"] = g.worldBox.lo[0] > g.worldBox.hi[0] ? py::object(py::none()) : py::object(fromBox(g.worldBox));
  d["metadata"] = g.metadata;
  d["text"] = describeGrid(g);
  return d;
}

// Registry and check report reach Python through the same JSON the CLI prints
// (registry_docs.cpp, check_report_format.cpp): one description, two front ends.
py::object fromJson(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

// Parts thinner than a cell the grid passed between (MeshingStats): grid edges of each kind.
py::dict thinPartsDict(const MeshingStats& s) {
  py::dict d;
  d["solid"] = s.thinSolidEdges;
  d["gaps"] = s.thinGapEdges;
  d["tips"] = s.tipEdges;
  d["example"] = py::make_tuple(s.thinExample[0], s.thinExample[1], s.thinExample[2]);
  d["refined_cubes"] = s.refinedCubes;
  if (!s.refinementSkipped.empty()) d["refinement_skipped"] = s.refinementSkipped;
  if (s.refinementLevelsReached > 1) {
    d["refined_levels"] = s.refinementLevelsReached;
    d["refined_deeper_cubes"] = s.refinedDeeperCubes;
  }
  if (!s.refinementDeeperSkipped.empty())
    d["refinement_deeper_skipped"] = s.refinementDeeperSkipped;
  return d;
}

// The export's report dict: the check's report (with 'text'), or printable None when there
// was no check; 'written', 'triangles', 'thin_parts', 'box', 'resolution', 'seconds' per stage.
py::dict exportResultDict(const ExportResult& result, const std::string& path) {
  py::dict d;
  if (result.checked) {
    d = fromJson(reportToJson(result.report, path)).cast<py::dict>();
    d["text"] = reportToText(result.report, path);
  } else {
    d["printable"] = py::none();
    d["text"] = "";
  }
  d["written"] = result.written;
  d["triangles"] = result.triangles;
  d["thin_parts"] = thinPartsDict(result.stats);
  d["checked_in_parts"] = result.checkedInParts;
  d["box"] = fromBox(result.box.box);
  d["resolution"] = result.box.resolution;
  d["seconds"] = py::make_tuple(result.seconds[0], result.seconds[1], result.seconds[2],
                                result.seconds[3]);
  return d;
}

}  // namespace
}  // namespace frep

PYBIND11_MODULE(_frepcore, m) {
  using namespace frep;
  m.doc() = "FRepCAD core: FRep trees, evaluation, meshing, checking and mesh files.";
  m.attr("DEFAULT_CELLS") = kDefaultCells;
  // Models may name mesh and OpenVDB files (mesh_sdf, vdb_grid nodes).
  registerVolumeSources();

  static py::exception<Cancelled> cancelled(m, "Cancelled");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Cancelled& e) {
      // (PyErr_SetString: pybind11 2.12 deprecates calling the exception object)
      PyErr_SetString(cancelled.ptr(), e.what());
    } catch (const ModelError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const FileError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });

  m.def(
      "set_threads",
      [](int threads) {
        static std::unique_ptr<tbb::global_control> limit;
        limit.reset();
        if (threads > 0)
          limit = std::make_unique<tbb::global_control>(
              tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
      },
      py::arg("threads"),
      "The most threads meshing and checking use in this process (0: every core). Brick "
      "jobs set it so that several workers on one machine share its cores.");
  m.def("use_one_job_memory_policy", &useLargePageHeap,
        "frepcad's memory policy (base/process_memory.h): one heap, never trimmed, a huge-page "
        "reserve. For a process that runs one export and exits (frepcad export --bricks), "
        "never for FreeCAD.");
  m.def(
      "node_types", [] { return fromJson(registryJson()); },
      "Every registered node type, as `frepcad info --json` lists them: type, category, doc, "
      "formula, inputs {min, max (None: any number)} and params.");
  m.def(
      "check_param",
      [](const std::string& typeId, const std::string& name, py::handle value) {
        const NodeType& type = registry().get(typeId);
        const ParamTemplate* t = type.findParam(name);
        if (!t) return type.unknownParamText(name);
        try {
          return t->check(toParamValue(*t, value, typeId));
        } catch (const ModelError& e) {
          return std::string(e.what());
        }
      },
      py::arg("type"), py::arg("name"), py::arg("value"),
      "What is wrong with a parameter value (\"-1 is out of range; allowed: (0, inf)\"), or "
      "an empty string when the registry allows it.");
  m.def("node_reference_markdown", [] { return registryMarkdown(); });

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
          [](PyNode& n, const std::string& path, py::object bbox, py::object resolution,
             py::object cells, const std::string& format, bool check, bool force,
             py::object progress, py::object tolerance, bool sharp, const std::string& mesher,
             bool fewerTriangles, bool refineThinParts, bool refineTips, bool straightenCreases,
             int refineLevels) {
            ExportRequest r;
            r.refinementLevels = refineLevels;
            r.straightenCreases = straightenCreases;
            r.extraction = parseMesher(mesher);
            r.flatVertices = fewerTriangles;
            r.refineThinParts = refineThinParts;
            r.refineTips = refineTips;
            r.box = boxRequest(bbox, resolution, cells, kPaddingCells);
            r.known = structuralBounds(n.node);
            if (!format.empty()) r.format = parseFormat(format);
            r.check = check;
            r.force = force;
            if (!tolerance.is_none()) r.tolerance = tolerance.cast<double>();
            r.sharpFeatures = sharp;
            n.compiled();
            std::shared_ptr<const Program> program = n.program;
            // Stages as one fraction for Python's progress: bounds 2 %, meshing to 40 %,
            // checking to 95 %, writing the rest.
            ExportResult result = runWithProgress<ExportResult>(
                [&](std::function<bool(double)> tick) {
                  r.progress = stagesAsOneFraction(tick, {0.0, 0.02, 0.4, 0.95, 1.0});
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
          py::arg("tolerance") = py::none(), py::arg("sharp") = true, py::arg("mesher") = "cubes",
          py::arg("fewer_triangles") = true, py::arg("refine_thin_parts") = false,
          py::arg("refine_tips") = false, py::arg("straighten_creases") = false,
          py::arg("refine_levels") = 1,
          "The export pipeline: box policy, mesh (mesher 'cubes' or 'tetra'; creases and "
          "corners placed unless sharp=False; the vertices where the surface is flat within a "
          "fiftieth of a cell dropped unless fewer_triangles=False; parts thinner than a cell "
          "meshed again at half a cell with refine_thin_parts=True, and the tips of creases and "
          "slivers with refine_tips=True, down to a cell / 2^refine_levels where they are "
          "thinner still), (creases straightened with straighten_creases=True: "
          "'straightened' in the dict), (simplify within `tolerance` of the surface), "
          "CGAL check, atomic write. Returns the check "
          "report dict plus 'written'; a refused mesh is not written unless force.")
      .def(
          "brick_plan",
          [](PyNode& n, py::object bbox, double resolution, bool sharp, const std::string& mesher,
             std::uint32_t jobs, bool fewerTriangles) {
            const BrickJobPlan plan =
                brickPlanOf(n, bbox, resolution, sharp, mesher, jobs, fewerTriangles);
            py::dict d;
            d["jobs"] = plan.jobs;
            d["bricks"] = py::make_tuple(plan.bricks[0], plan.bricks[1], plan.bricks[2]);
            d["split"] = py::make_tuple(plan.split[0], plan.split[1], plan.split[2]);
            d["run_id"] = plan.runId;
            return d;
          },
          py::arg("bbox"), py::arg("resolution"), py::arg("sharp") = true,
          py::arg("mesher") = "cubes", py::arg("jobs") = 1, py::arg("fewer_triangles") = true,
          "A brick-job run (issue 17): the mesher's bricks per axis, the jobs per axis and the "
          "run's id. ValueError for a job count the bricks cannot take.")
      .def(
          "brick_job",
          [](PyNode& n, py::object bbox, double resolution, bool sharp, const std::string& mesher,
             std::uint32_t jobs, std::uint32_t job, const std::string& path, bool fewerTriangles) {
            const BrickJobPlan plan =
                brickPlanOf(n, bbox, resolution, sharp, mesher, jobs, fewerTriangles);
            const auto start = std::chrono::steady_clock::now();
            MeshPiece piece;
            {
              py::gil_scoped_release release;
              piece = runBrickJob(n.compiled(), plan, job);
              writePieceFile(piece, path);
              // the job judges its own piece for the check too: the merge then reads only
              // the summary (a few per cent of the piece) instead of checking the piece
              const std::vector<char> summary = judgeBrickPiece(plan, piece);
              AtomicFile out(path + ".check");
              out.write(summary.data(), summary.size());
              out.commit();
            }
            py::dict d;
            d["job"] = job;
            d["path"] = path;
            d["vertices"] = piece.keys.size();
            d["triangles"] = piece.triangles.size();
            d["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            return d;
          },
          py::arg("bbox"), py::arg("resolution"), py::arg("sharp"), py::arg("mesher"),
          py::arg("jobs"), py::arg("job"), py::arg("path"), py::arg("fewer_triangles") = true,
          "Meshes job `job` of the run into a piece file at `path` (written atomically).")
      .def(
          "merge_bricks",
          [](PyNode& n, py::object bbox, double resolution, bool sharp, const std::string& mesher,
             std::uint32_t jobs, const std::vector<std::string>& pieces, const std::string& path,
             const std::string& format, bool check, bool force, py::object progress,
             const std::string& unit,
             const std::vector<std::pair<std::string, std::string>>& metadata,
             bool fewerTriangles) {
            const BrickJobPlan plan =
                brickPlanOf(n, bbox, resolution, sharp, mesher, jobs, fewerTriangles);
            ExportRequest r;
            if (!format.empty()) r.format = parseFormat(format);
            if (!unit.empty()) r.threeMf.unit = parseLengthUnit(unit);
            r.threeMf.metadata = metadata;
            r.check = check;
            r.force = force;
            // merging to 30 %, checking to 95 %, writing the rest
            ExportResult result = runWithProgress<ExportResult>(
                [&](std::function<bool(double)> tick) {
                  r.progress = stagesAsOneFraction(tick, {0.0, 0.0, 0.3, 0.95, 1.0});
                  // the jobs' check summaries, where every piece has one
                  std::vector<std::string> summaries;
                  for (const std::string& piece : pieces)
                    if (std::filesystem::exists(piece + ".check")) summaries.push_back(piece + ".check");
                  if (summaries.size() != pieces.size()) summaries.clear();
                  return exportPieces(plan, pieces, r, path, summaries);
                },
                progress);
            return exportResultDict(result, path);
          },
          py::arg("bbox"), py::arg("resolution"), py::arg("sharp"), py::arg("mesher"),
          py::arg("jobs"), py::arg("pieces"), py::arg("path"), py::arg("format") = "",
          py::arg("check") = true, py::arg("force") = false, py::arg("progress") = py::none(),
          py::arg("unit") = "",
          py::arg("metadata") = std::vector<std::pair<std::string, std::string>>(),
          py::arg("fewer_triangles") = true,
          "Welds the run's piece files (one per job, in job order), checks the mesh and "
          "writes `path` atomically (a binary STL or a 3MF streamed, never whole in memory; "
          "unit and metadata for a 3MF): the export's report dict plus 'written'.")
      .def(
          "mesh",
          [](PyNode& n, py::object bbox, double resolution, py::object progress, bool normals,
             py::object tolerance, bool sharp, const std::string& mesher, bool fewerTriangles,
             bool refineThinParts, bool refineTips, bool straighten, int refineLevels) {
            if (straighten && !sharp)
              throw ModelError(
                  "straighten_creases needs sharp=True (the creases are found by "
                  "the sharp features)");
            MeshingOptions o;
            o.extraction = parseMesher(mesher);
            o.sharpFeatures = sharp;
            o.flatVertices = fewerTriangles;
            o.refineThinParts = refineThinParts;
            o.refineTips = refineTips;
            o.refinementLevels = refineLevels;
            o.bbox = toBox(bbox.cast<py::sequence>());
            o.resolution = resolution;
            o.normals = normals;
            // A preview too large for the memory is refused with the figures, before any
            // allocation (FreeCAD would die with the process).
            o.memoryBudget = availableMemory();
            Finishing finishing;
            finishing.straightenCreases = straighten;
            if (!tolerance.is_none()) finishing.tolerance = tolerance.cast<double>();
            n.compiled();
            std::shared_ptr<const Program> program = n.program;
            auto stats = std::make_shared<MeshingStats>();
            auto straightened = std::make_shared<SimplifyStats>();
            py::object mesh = py::cast(runWithProgress<TriangleMesh>(
                [program, o, finishing, stats,
                 straightened](std::function<bool(double)> tick) mutable {
                  FinishedMesh m = meshAndFinish(*program, o, finishing, tick, false);
                  *stats = std::move(m.stats);
                  *straightened = m.straighten;
                  return std::move(m.mesh);
                },
                progress));
            mesh.attr("thin_parts") = thinPartsDict(*stats);
            if (straighten)
              mesh.attr("straightened") = py::dict(py::arg("merged") = straightened->collapses,
                                                   py::arg("flipped") = straightened->flips,
                                                   py::arg("seconds") = straightened->seconds);
            return mesh;
          },
          py::arg("bbox"), py::arg("resolution"), py::arg("progress") = py::none(),
          py::arg("normals") = false, py::arg("tolerance") = py::none(), py::arg("sharp") = true,
          py::arg("mesher") = "cubes", py::arg("fewer_triangles") = true,
          py::arg("refine_thin_parts") = false, py::arg("refine_tips") = false,
          py::arg("straighten_creases") = false, py::arg("refine_levels") = 1,
          "Polygonises inside bbox with cells of at most `resolution` (mesher 'cubes', or "
          "'tetra': marching tetrahedra, three times the triangles; the vertices where the "
          "surface is flat within a fiftieth of a cell dropped unless fewer_triangles=False); with "
          "a "
          "tolerance the "
          "mesh is then simplified within it of the surface (creases and corners placed "
          "unless sharp=False), after its creases are straightened with "
          "straighten_creases=True (the mesh's straightened then says {'merged', 'flipped', "
          "'seconds'}). progress(fraction) is called on this thread; returning False "
          "cancels "
          "(raises Cancelled). The mesh's thin_parts says where parts thinner than a cell "
          "passed between the grid's points: {'solid': grid edges of solid left out, 'gaps': "
          "of gaps closed (both with no surface near), 'tips': of crease tips cut short, "
          "'example': a point on one, 'refined_cubes': the cubes round them meshed again at "
          "half a cell with refine_thin_parts=True (and round the tips with refine_tips=True), "
          "and with refine_levels > 1 'refined_levels' and 'refined_deeper_cubes': the "
          "smaller cubes meshed again below that, down to a cell / 2^refined_levels}.")
      .def(
          "to_vdb",
          [](PyNode& n, const std::string& path, py::object bbox, double voxel, double halfWidth,
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
      [](const std::string& text, const std::string& source, const std::string& folder) {
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
      [](const std::string& path) {
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
      [](const std::string& path, const std::string& grid, double iso, double adaptivity) {
        py::gil_scoped_release release;
        const GridSet grids = readVdb(path);
        return levelSetToMesh(grids, grids.scalarGrid(grid, path), iso, adaptivity);
      },
      py::arg("path"), py::arg("grid") = "", py::arg("iso") = 0.0, py::arg("adaptivity") = 0.0,
      "OpenVDB's volumeToMesh of a grid of a .vdb file (the first float or double grid when "
      "`grid` is empty), outward-oriented; judge it with Mesh.check() before printing.");

  py::class_<TriangleMesh>(m, "Mesh", py::dynamic_attr(),
                           "An indexed triangle mesh (float coordinates).")
      .def(py::init([](const std::vector<Vec3f>& points, const std::vector<Triangle>& triangles) {
             TriangleMesh t;
             t.positions = points;
             t.triangles = triangles;
             for (const Triangle& f : t.triangles)
               for (std::uint32_t v : f)
                 if (v >= t.positions.size())
                   throw ModelError("Mesh: triangle corner " + std::to_string(v) +
                                    " refers to no point; allowed: 0 to " +
                                    std::to_string(t.positions.size()) + " - 1");
             return t;
           }),
           py::arg("points"), py::arg("triangles"),
           "A mesh from points (x, y, z) and triangles (three point indices each).")
      .def_property_readonly("vertex_count", &TriangleMesh::vertexCount)
      .def_property_readonly("triangle_count", &TriangleMesh::triangleCount)
      .def_property_readonly("points", [](const TriangleMesh& t) { return t.positions; })
      .def_property_readonly("triangles", [](const TriangleMesh& t) { return t.triangles; })
      .def("volume", &meshVolume, "Enclosed signed volume (no checks).")
      .def("area", &meshArea)
      .def(
          "check",
          [](const TriangleMesh& t, const std::string& name, py::object progress) {
            CheckReport r = runWithProgress<CheckReport>(
                [&t](std::function<bool(double)>) { return checkMesh(t); }, progress);
            py::dict d = fromJson(reportToJson(r, name));
            d["text"] = reportToText(r, name);
            return d;
          },
          py::arg("name") = "mesh", py::arg("progress") = py::none(),
          "CGAL printability check: the dict of `frepcad check --json` plus 'text', the report.")
      .def(
          "write",
          [](const TriangleMesh& t, const std::string& path, const std::string& format,
             py::object progress) {
            MeshFormat f = format.empty() ? formatFromPath(path) : parseFormat(format);
            runWithProgress<bool>(
                [&](std::function<bool(double)> tick) {
                  writeMesh(t, path, f, tick);
                  return true;
                },
                progress);
          },
          py::arg("path"), py::arg("format") = "", py::arg("progress") = py::none(),
          "Writes through a temporary file and a rename: a cancel or failure leaves no file.")
      .def(
          "repair",
          [](const TriangleMesh& t, const std::string& rebuild, double voxel, double weld,
             bool fillHoles, const std::string& name, py::object progress) {
            RepairOptions o;
            o.rebuild = parseRebuildPolicy(rebuild);
            o.voxel = voxel;
            o.weldDistance = weld;
            o.fillHoles = fillHoles;
            RepairResult r = runWithProgress<RepairResult>(
                [&](std::function<bool(double)> tick) {
                  o.progress = tick;
                  return repairMesh(t, o, name);
                },
                progress);
            py::dict d;
            d["printable"] = r.printable();
            d["printable_before"] = r.before.printable();
            d["actions"] = r.actions;
            d["reasons_before"] = r.before.reasons;
            d["reasons"] = r.after.reasons;
            d["rebuilt"] = r.rebuilt;
            d["voxel"] = r.voxel;
            d["deviation"] = r.deviation.hausdorff();
            d["result_to_input"] = r.deviation.bToA;
            d["input_to_result"] = r.deviation.aToB;
            d["check"] = fromJson(reportToJson(r.after, name));
            d["text"] = repairToText(r, r.after, name);
            return py::make_tuple(std::move(r.mesh), d);
          },
          py::arg("rebuild") = "auto", py::arg("voxel") = 0.0, py::arg("weld") = -1.0,
          py::arg("fill_holes") = true, py::arg("name") = "mesh", py::arg("progress") = py::none(),
          "Makes the mesh printable (docs/manufacturing.md): (repaired Mesh, report dict with "
          "printable, actions, reasons, rebuilt, deviation, check, text). The mesh itself is "
          "not changed; a result that is still not printable says why in 'reasons'.")
      .def(
          "printability",
          [](const TriangleMesh& t, const Vec3& up, double overhang, py::object minWall,
             double density, const std::string& name) {
            PrintabilityOptions o;
            o.up = up;
            o.overhangDeg = overhang;
            if (!minWall.is_none()) o.minWall = minWall.cast<double>();
            o.density = density;
            PrintabilityReport p;
            CheckReport c;
            {
              py::gil_scoped_release release;
              p = measurePrintability(t, o);
              c = checkMesh(t);
              addPrintabilityReasons(c, p, o);
            }
            py::dict d = fromJson(printabilityToJson(c, p, o, name)).cast<py::dict>();
            d["thickness"] = p.thickness;
            d["text"] = reportToText(c, name) + printabilityToText(p, o);
            return d;
          },
          py::arg("up") = Vec3{0, 0, 1}, py::arg("overhang") = 45.0,
          py::arg("min_wall") = py::none(), py::arg("density") = 0.0, py::arg("name") = "mesh",
          "The check plus what a printer makes of the mesh: dict of `frepcad check --print "
          "--json` ('print': min_wall, thin_triangles, overhang_area, height, mass_g, ...), "
          "'thickness' per triangle (-1 where not measured) and 'text'.")
      .def(
          "deviation",
          [](const TriangleMesh& a, const TriangleMesh& b) {
            DeviationReport r;
            {
              py::gil_scoped_release release;
              r = meshDeviation(a, b);
            }
            py::dict d;
            d["hausdorff"] = r.hausdorff();
            d["a_to_b"] = r.aToB;
            d["b_to_a"] = r.bToA;
            d["mean_a_to_b"] = r.meanAToB;
            d["mean_b_to_a"] = r.meanBToA;
            return d;
          },
          py::arg("other"), "The Hausdorff distance to another mesh, both ways, sampled.");

  m.def("materials", [] {
    py::dict d;
    for (const Material& x : materials()) d[x.name] = x.density;
    return d;
  }, "The printing materials the printability report knows: name -> density in g/cm3.");
  m.def(
      "read_3mf",
      [](const std::string& path) {
        ThreeMfContents c;
        {
          py::gil_scoped_release release;
          c = read3mf(path);
        }
        py::list objects;
        for (NamedMesh& o : c.objects) objects.append(py::make_tuple(o.name, std::move(o.mesh)));
        py::dict d;
        d["objects"] = objects;
        d["unit"] = lengthUnitName(c.unit);
        py::dict meta;
        for (const auto& [k, v] : c.metadata) meta[py::str(k)] = v;
        d["metadata"] = meta;
        return d;
      },
      py::arg("path"),
      "A 3MF file's build: dict(objects=[(name, Mesh)], unit, metadata). Hostile packages "
      "(zip bombs, deep components) are refused with OSError before they are read.");
  m.def(
      "write_3mf",
      [](const std::vector<std::pair<std::string, TriangleMesh>>& objects, const std::string& path,
         const std::string& unit, const std::map<std::string, std::string>& metadata, bool force,
         py::object progress) {
        std::vector<NamedMesh> named;
        for (const auto& [n, mesh] : objects) named.push_back({n, mesh});
        ThreeMfOptions o;
        o.unit = parseLengthUnit(unit);
        for (const auto& kv : metadata) o.metadata.push_back(kv);
        ThreeMfExportResult r = runWithProgress<ThreeMfExportResult>(
            [&](std::function<bool(double)> tick) {
              return export3mf(named, o, path, force, tick);
            },
            progress);
        py::dict d;
        d["printable"] = r.printable();
        d["written"] = r.written;
        py::list reports;
        std::string text;
        for (std::size_t i = 0; i < r.reports.size(); ++i) {
          const std::string name = path + ": " + named[i].name;
          py::dict one = fromJson(reportToJson(r.reports[i], name)).cast<py::dict>();
          one["name"] = named[i].name;
          reports.append(one);
          text += reportToText(r.reports[i], name);
        }
        d["objects"] = reports;
        d["text"] = text;
        return d;
      },
      py::arg("objects"), py::arg("path"), py::arg("unit") = "mm",
      py::arg("metadata") = std::map<std::string, std::string>(), py::arg("force") = false,
      py::arg("progress") = py::none(),
      "Several meshes as the objects of one 3MF: each object as the file holds it (lib3mf "
      "rounds coordinates) is checked; the file is written atomically only when all pass, or "
      "with force. Returns dict(printable, written, objects=[check report dicts], text).");

  py::class_<FfdLattice>(m, "Lattice",
                         "A Sederberg-Parry FFD lattice: a rest box divided l x m x n times and "
                         "its (l+1)(m+1)(n+1) control points (index i slowest, k fastest).")
      .def(py::init([](const Vec3& lo, const Vec3& hi, const std::array<int, 3>& d,
                       const py::object& points) {
             FfdLattice l({lo, hi}, d[0], d[1], d[2]);
             if (!points.is_none()) l.setPoints(points.cast<std::vector<Vec3>>());
             return l;
           }),
           py::arg("rest_min"), py::arg("rest_max"), py::arg("divisions"),
           py::arg("points") = py::none())
      .def_property_readonly("rest_min", [](const FfdLattice& l) { return l.rest().lo; })
      .def_property_readonly("rest_max", [](const FfdLattice& l) { return l.rest().hi; })
      .def_property_readonly("divisions", [](const FfdLattice& l) {
        return std::array<int, 3>{l.divisions(0), l.divisions(1), l.divisions(2)};
      })
      .def_property_readonly("points", &FfdLattice::points)
      .def("rest_points", [](const FfdLattice& l) {
        return FfdLattice(l.rest(), l.divisions(0), l.divisions(1), l.divisions(2)).points();
      }, "The undeformed control points.")
      .def("set_point", &FfdLattice::setPoint, py::arg("i"), py::arg("j"), py::arg("k"),
           py::arg("point"))
      .def("deform", &FfdLattice::deform, py::arg("point"),
           "A point moved by the lattice (points outside the rest box do not move).")
      .def("inverse", [](const FfdLattice& l, const Vec3& y) -> py::object {
        if (auto s = l.inverse(y)) return py::cast(l.restPoint(*s));
        return py::none();
      }, py::arg("point"), "The rest-space point the lattice moves to `point`, or None.")
      .def("find_fold", [](const FfdLattice& l) -> py::object {
        if (auto f = l.findFold()) return py::str(f->text());
        return py::none();
      }, "None, or where the lattice folds over itself (its cell), as text.")
      .def("to_json", &latticeToJson, "The lattice file's text (docs/file-formats.md).")
      .def("write", &writeLatticeFile, py::arg("path"), "Writes a lattice file atomically.");
  m.def("read_lattice", &readLatticeFile, py::arg("path"));
  m.def("parse_lattice", &parseLattice, py::arg("text"), py::arg("source") = "lattice");
  m.def(
      "deform_mesh",
      [](const TriangleMesh& mesh, const FfdLattice& lattice, py::object progress) {
        return runWithProgress<TriangleMesh>(
            [&](std::function<bool(double)> tick) {
              MeshFfdOptions o;
              o.progress = tick;
              return deformMesh(mesh, lattice, o);
            },
            progress);
      },
      py::arg("mesh"), py::arg("lattice"), py::arg("progress") = py::none(),
      "The mesh with every vertex in the rest box moved by the lattice (judge it with "
      "check() before printing: a folding lattice can make it self-intersect).");
  m.def(
      "deform_vdb",
      [](const std::string& input, const std::string& output, const FfdLattice& lattice,
         const std::string& interpolation, bool keepVectors, bool rebuild, bool splat,
         py::object progress) {
        GridFfdOptions o;
        if (interpolation == "nearest") o.interpolation = 0;
        else if (interpolation == "linear") o.interpolation = 1;
        else if (interpolation == "quadratic") o.interpolation = 2;
        else throw ModelError("deform_vdb: interpolation '" + interpolation +
                              "' is not allowed; allowed: nearest, linear, quadratic");
        o.keepVectors = keepVectors;
        o.rebuildLevelSets = rebuild;
        if (splat) o.method = GridFfdOptions::Method::ForwardSplat;
        const GridSet out = runWithProgress<GridSet>(
            [&](std::function<bool(double)> tick) {
              o.progress = tick;
              return deformGrids(readVdb(input), lattice, o);
            },
            progress);
        {
          py::gil_scoped_release release;
          writeVdb(out, output);
        }
        py::list grids;
        for (std::size_t i = 0; i < out.size(); ++i) grids.append(gridInfoDict(out.info(i)));
        return grids;
      },
      py::arg("input"), py::arg("output"), py::arg("lattice"), py::arg("interpolation") = "linear",
      py::arg("keep_vectors") = false, py::arg("rebuild") = true, py::arg("splat") = false,
      py::arg("progress") = py::none(),
      "Every grid of a .vdb file deformed by the lattice (backward resampling: no gaps; "
      "splat=True: seed 002's forward splatting, for comparison) and written atomically; "
      "returns the written grids as vdb_grids does.");

  m.def(
      "read_mesh",
      [](const std::string& path) {
        py::gil_scoped_release release;
        return readMesh(path);
      },
      py::arg("path"));

  bindHSpline(m);
}

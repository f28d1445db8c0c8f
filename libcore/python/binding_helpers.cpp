#include "python/binding_helpers.h"

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

namespace frep {

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
      if (py::isinstance<py::str>(q) || !py::isinstance<py::sequence>(q) || py::len(q) != 3)
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

// An export's progress by stage as one bar: the stages (bounds, meshing, checking, writing)
// its phases, in proportion to `weights`.
std::function<bool(ExportStage, double)> stagesAsPhases(const std::function<bool(double)>& tick,
                                                        std::initializer_list<double> weights) {
  const std::vector<Progress> phase = Progress(tick).phases(weights);
  return [phase](ExportStage s, double f) { return phase[static_cast<int>(s)].report(f); };
}

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
BrickJobPlan brickPlanOf(PyNode& n, const py::object& bbox, double resolution, std::uint32_t jobs,
                         const MeshSettings& settings) {
  MeshingBox box{toBox(bbox.cast<py::sequence>()), resolution};
  Model model;
  model.root = n.node;
  return planBrickJobs(box, settings, jobs, textFingerprint(modelToJson(model)));
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

BoxRequest boxRequest(const py::object& bbox, const py::object& resolution, const py::object& cells,
                      double paddingCells) {
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
  d["box"] = g.worldBox.lo[0] > g.worldBox.hi[0] ? py::object(py::none())
                                                 : py::object(fromBox(g.worldBox));
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
  d["seconds"] =
      py::make_tuple(result.seconds[0], result.seconds[1], result.seconds[2], result.seconds[3]);
  return d;
}

}  // namespace frep

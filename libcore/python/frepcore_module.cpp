// _frepcore: the thin pybind11 layer over libcore. It converts Python values to libcore types
// and back, releases the GIL for long work, and runs that work on a worker thread so that the
// Python progress callback is always called on the caller's thread (FreeCAD's progress bar and
// its cancel live in the GUI thread). The pythonic modelling API is in frepcore/__init__.py.
// This file holds the module and its errors; each subject binds itself in a file of its own
// (python/bindings.h).
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
#include "python/binding_helpers.h"
#include "python/bindings.h"
#include "repair/repair.h"
#include "simplify/straighten_creases.h"
#include "volume/field_sources.h"
#include "volume/grid_ffd.h"
#include "volume/grid_set.h"
#include "volume/level_sets.h"

PYBIND11_MODULE(_frepcore, m) {
  using namespace frep;
  m.doc() = "FRepCAD core: FRep trees, evaluation, meshing, checking and mesh files.";
  m.attr("DEFAULT_CELLS") = kDefaultCells;
  m.attr("__version__") = FREPCAD_VERSION;
  // The exit statuses of frepcad (base/exit_status.h), for the Python children it runs.
  py::dict exits;
  exits["done"] = exitStatus(Outcome::Done);
  exits["not_printable"] = exitStatus(Outcome::NotPrintable);
  exits["bad_input"] = exitStatus(Outcome::BadInput);
  exits["internal_error"] = exitStatus(Outcome::InternalError);
  exits["cancelled"] = exitStatus(Outcome::Cancelled);
  m.attr("EXIT_STATUS") = exits;
  // Models may name mesh and OpenVDB files (mesh_sdf, vdb_grid nodes).
  registerVolumeSources();
  bindVdbReader(m);

  static py::exception<Cancelled> cancelled(m, "Cancelled");
  // A ValueError to callers that only know that; frepcore.exit_status_of reads it as "not
  // printable", as frepcad does.
  static py::exception<EmptySolidError> emptySolid(m, "EmptySolid", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Cancelled& e) {
      // (PyErr_SetString: pybind11 2.12 deprecates calling the exception object)
      PyErr_SetString(cancelled.ptr(), e.what());
    } catch (const EmptySolidError& e) {
      PyErr_SetString(emptySolid.ptr(), e.what());
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

  bindMeshSettings(m);
  bindNode(m);
  bindMesh(m);
  bindLattice(m);
  bindHSpline(m);
}

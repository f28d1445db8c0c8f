// What the binding files of the frepcore module share (frepcore_module.cpp, *_bindings.cpp):
// conversions between Python values and libcore's, the wrapped node, and long work run on a
// worker thread with the Python progress callback called on the caller's thread.
#pragma once

#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <initializer_list>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "base/errors.h"
#include "base/vec.h"
#include "frep/bounds.h"
#include "frep/program.h"
#include "frep/registry.h"
#include "frep/tree.h"
#include "mesh/mesher.h"
#include "pipeline/brick_jobs.h"
#include "pipeline/export_pipeline.h"
#include "volume/grid_set.h"

namespace frep {

namespace py = pybind11;

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

// ---- wrapped types --------------------------------------------------------------------------

struct PyNode {
  NodePtr node;
  std::shared_ptr<const Program> program;  // compiled on first use

  const Program& compiled() {
    if (!program) program = std::make_shared<const Program>(compile(node));
    return *program;
  }
};

// ---- values -------------------------------------------------------------------------------
ParamValue toParamValue(const ParamTemplate& t, const py::handle& v, const std::string& where);

py::object fromParamValue(const ParamTemplate& t, const ParamValue& v);

Box3 toBox(const py::sequence& s);

py::tuple fromBox(const Box3& b);

// An export's progress by stage as one bar: the stages (bounds, meshing, checking, writing)
// its phases, in proportion to `weights`.
std::function<bool(ExportStage, double)> stagesAsPhases(const std::function<bool(double)>& tick,
                                                        std::initializer_list<double> weights);

PyNode makePyNode(const std::string& typeId, const py::dict& params,
                  const std::vector<PyNode>& inputs, const std::string& path);

// A brick-job run of this solid (pipeline/brick_jobs.h); the run's id fingerprints the
// tree's canonical JSON, so the driver and every worker agree on it.
BrickJobPlan brickPlanOf(PyNode& n, const py::object& bbox, double resolution, std::uint32_t jobs,
                         const MeshSettings& settings);

py::dict nodeParams(const PyNode& n);

py::dict boundsDict(const SolidBounds& b);

SolidBounds boundsFromDict(const py::dict& d);

BoxRequest boxRequest(const py::object& bbox, const py::object& resolution, const py::object& cells,
                      double paddingCells);

py::dict gridInfoDict(const GridInfo& g);

// Registry and check report reach Python through the same JSON the CLI prints
// (registry_docs.cpp, check_report_format.cpp): one description, two front ends.
py::object fromJson(const std::string& text);

// Parts thinner than a cell the grid passed between (MeshingStats): grid edges of each kind.
py::dict thinPartsDict(const MeshingStats& s);

// The export's report dict: the check's report (with 'text'), or printable None when there
// was no check; 'written', 'triangles', 'thin_parts', 'box', 'resolution', 'seconds' per stage.
py::dict exportResultDict(const ExportResult& result, const std::string& path);

// A file path from Python: a str or any os.PathLike (pathlib.Path), as open() takes it. A NUL
// inside is refused (ValueError) rather than cut off by the C library, which would read or
// write a file of the shorter name.
struct FilePath {
  std::string value;
  operator const std::string&() const { return value; }
};

}  // namespace frep

namespace pybind11::detail {

template <>
struct type_caster<frep::FilePath> {
  PYBIND11_TYPE_CASTER(frep::FilePath, const_name("str | os.PathLike"));
  bool load(handle source, bool) {
    if (!source || source.is_none()) return false;
    object path;
    try {
      path = module_::import("os").attr("fspath")(source);
    } catch (error_already_set&) {
      return false;  // not a path: pybind11's TypeError lists what is accepted
    }
    if (!isinstance<str>(path)) return false;  // bytes paths: not taken
    value.value = path.cast<std::string>();
    if (value.value.find('\0') != std::string::npos)
      throw value_error("path " + repr(path).cast<std::string>().substr(0, 200) +
                        ": a file name cannot hold a NUL character");
    return true;
  }
  static handle cast(const frep::FilePath& p, return_value_policy, handle) {
    return str(p.value).release();
  }
};

}  // namespace pybind11::detail

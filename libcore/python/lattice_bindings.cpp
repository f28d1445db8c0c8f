// frepcore's lattices: the Lattice class and the deformation of meshes and volumes.
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
#include "python/binding_helpers.h"
#include "python/bindings.h"
#include "repair/repair.h"
#include "simplify/straighten_creases.h"
#include "volume/field_sources.h"
#include "volume/grid_ffd.h"
#include "volume/grid_set.h"
#include "volume/level_sets.h"

namespace frep {

void bindLattice(py::module_& m) {
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
      .def_property_readonly(
          "divisions",
          [](const FfdLattice& l) {
            return std::array<int, 3>{l.divisions(0), l.divisions(1), l.divisions(2)};
          })
      .def_property_readonly("points", &FfdLattice::points)
      .def(
          "rest_points",
          [](const FfdLattice& l) {
            return FfdLattice(l.rest(), l.divisions(0), l.divisions(1), l.divisions(2)).points();
          },
          "The undeformed control points.")
      .def("set_point", &FfdLattice::setPoint, py::arg("i"), py::arg("j"), py::arg("k"),
           py::arg("point"))
      .def("deform", &FfdLattice::deform, py::arg("point"),
           "A point moved by the lattice (points outside the rest box do not move).")
      .def(
          "inverse",
          [](const FfdLattice& l, const Vec3& y) -> py::object {
            if (auto s = l.inverse(y)) return py::cast(l.restPoint(*s));
            return py::none();
          },
          py::arg("point"), "The rest-space point the lattice moves to `point`, or None.")
      .def(
          "find_fold",
          [](const FfdLattice& l) -> py::object {
            if (auto f = l.findFold()) return py::str(f->text());
            return py::none();
          },
          "None, or where the lattice folds over itself (its cell), as text.")
      .def("to_json", &latticeToJson, "The lattice file's text (docs/file-formats.md).")
      .def(
          "write", [](const FfdLattice& l, const FilePath& path) { writeLatticeFile(l, path); },
          py::arg("path"), "Writes a lattice file atomically.");
  m.def(
      "read_lattice", [](const FilePath& path) { return readLatticeFile(path); }, py::arg("path"));
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
        if (interpolation == "nearest")
          o.interpolation = 0;
        else if (interpolation == "linear")
          o.interpolation = 1;
        else if (interpolation == "quadratic")
          o.interpolation = 2;
        else
          throw ModelError("deform_vdb: interpolation '" + interpolation +
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
}

}  // namespace frep

// frepcore's meshes: the Mesh class (check, write, repair, printability, deviation), mesh
// files and 3MF packages.
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

void bindMesh(py::module_& m) {
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
          [](const TriangleMesh& t, const FilePath& path, const std::string& format,
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
             bool fillHoles, double maxDeviation, bool allowMorePieces, const std::string& name,
             py::object progress) {
            RepairOptions o;
            o.maxDeviation = maxDeviation;
            o.allowMorePieces = allowMorePieces;
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
            d["accepted"] = r.accepted();
            d["departures"] = r.departures;
            d["deviation_bound"] = r.deviationBound;
            d["printable_before"] = r.before.printable();
            d["actions"] = r.actions;
            d["reasons_before"] = r.before.reasons;
            d["reasons"] = r.after.reasons;
            d["rebuilt"] = r.rebuilt;
            d["voxel"] = r.voxel;
            d["deviation"] = r.deviation.hausdorff();
            d["result_to_input"] = r.deviation.bToA;
            d["input_to_result"] = r.lostDistance;
            d["check"] = fromJson(reportToJson(r.after, name));
            d["text"] = repairToText(r, r.after, name);
            return py::make_tuple(std::move(r.mesh), d);
          },
          py::arg("rebuild") = "auto", py::arg("voxel") = 0.0, py::arg("weld") = -1.0,
          py::arg("fill_holes") = true, py::arg("max_deviation") = -1.0,
          py::arg("allow_more_pieces") = false, py::arg("name") = "mesh",
          py::arg("progress") = py::none(),
          "Makes the mesh printable (docs/manufacturing.md): (repaired Mesh, report dict with "
          "accepted, printable, actions, reasons, departures, rebuilt, deviation, check, text). "
          "The mesh itself is not changed; 'accepted' is printable and faithful to the input "
          "(no more pieces, within max_deviation: < 0 is 2 % of the diagonal); 'reasons' and "
          "'departures' say why not.")
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
              c = checkMesh(t);
              o.thickness = c.printable();
              p = measurePrintability(t, o);
              addPrintabilityReasons(c, p, o);
            }
            py::dict d = fromJson(printabilityToJson(c, p, o, name)).cast<py::dict>();
            d["thickness"] = p.thickness;
            d["cavity_of"] = p.cavityOf;
            d["text"] = reportToText(c, name) + printabilityToText(p, o);
            return d;
          },
          py::arg("up") = Vec3{0, 0, 1}, py::arg("overhang") = 45.0,
          py::arg("min_wall") = py::none(), py::arg("density") = 0.0, py::arg("name") = "mesh",
          "The check plus what a printer makes of the mesh: dict of `frepcad check --print "
          "--json` ('print': min_wall, thin_triangles, overhang_area, height, mass_g, ...), "
          "'thickness' per triangle (-1 where not measured), 'cavity_of' per triangle (the index "
          "in print['cavity_list'] of the cavity it walls, or -1; empty when not counted) and "
          "'text'.")
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

  m.def(
      "materials",
      [] {
        py::dict d;
        for (const Material& x : materials()) d[x.name] = x.density;
        return d;
      },
      "The printing materials the printability report knows: name -> density in g/cm3.");
  m.def(
      "read_3mf",
      [](const FilePath& path) {
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
      "read_3mf_beams",
      [](const FilePath& path) {
        ThreeMfBeams b;
        {
          py::gil_scoped_release release;
          b = read3mfBeams(path);
        }
        return py::dict(py::arg("beams") = b.beams, py::arg("clipped") = b.clipped);
      },
      py::arg("path"),
      "The beams of a 3MF's beam lattices as lib3mf reads them: dict(beams, clipped: the "
      "lattices clipped by a mesh).");
  m.def(
      "write_3mf",
      [](const std::vector<std::pair<std::string, TriangleMesh>>& objects, const FilePath& path,
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
          const std::string name = path.value + ": " + named[i].name;
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

  m.def(
      "read_mesh",
      [](const FilePath& path) {
        py::gil_scoped_release release;
        return readMesh(path);
      },
      py::arg("path"));
}

}  // namespace frep

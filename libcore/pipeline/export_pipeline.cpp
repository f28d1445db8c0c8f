#include "pipeline/export_pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <sstream>

#include "base/errors.h"
#include "base/phase_times.h"
#include "base/process_memory.h"
#include "base/progress.h"

namespace frep {

namespace fs = std::filesystem;

namespace {

std::string sideNames(const SolidBounds& b) {
  static const char* names[3][2] = {{"-x", "+x"}, {"-y", "+y"}, {"-z", "+z"}};
  std::string s;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side)
      if (b.unbounded[a][side]) s += (s.empty() ? "" : ", ") + std::string(names[a][side]);
  return s;
}

double longestSide(const Box3& b) {
  return std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]});
}

void checkRequest(const BoxRequest& r) {
  if (r.resolution && !(*r.resolution > 0.0 && std::isfinite(*r.resolution)))
    throw ModelError("resolution (cell size) must be a number > 0");
  if (r.cells && (*r.cells < 1 || *r.cells > kMaxCells))
    throw ModelError("cells must be between 1 and " + std::to_string(kMaxCells) + ", got " +
                     std::to_string(*r.cells));
  if (r.bbox) {
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(r.bbox->lo[a]) || !std::isfinite(r.bbox->hi[a]) ||
          !(r.bbox->lo[a] < r.bbox->hi[a]))
        throw ModelError("bounding box must be finite with min < max on every axis");
  }
}

double cellSize(const BoxRequest& r, double longest) {
  if (r.resolution) return *r.resolution;
  return longest / static_cast<double>(r.cells.value_or(kDefaultCells));
}

}  // namespace

MeshingBox chooseBox(const SolidBounds& b, const BoxRequest& r) {
  checkRequest(r);
  if (r.bbox) return {*r.bbox, cellSize(r, longestSide(*r.bbox))};
  if (b.empty) throw EmptySolidError("the solid is empty: no point is inside, nothing to print");
  if (!b.bounded())
    throw ModelError("the solid is unbounded towards " + sideNames(b) +
                     "; give a bounding box or intersect it with a bounded solid");
  const double longest = std::max(longestSide(b.box), 1e-9);
  MeshingBox m{b.box, cellSize(r, longest)};
  const double pad = r.paddingCells * m.resolution + 1e-3 * longest;
  for (int a = 0; a < 3; ++a) {
    m.box.lo[a] -= pad;
    m.box.hi[a] += pad;
  }
  return m;
}

MeshingBox chooseBox(const Field& field, const Box3& known, const BoxRequest& r) {
  checkRequest(r);
  if (r.bbox) return chooseBox(SolidBounds{}, r);
  BoundsOptions o;
  o.known = known;
  return chooseBox(findBounds(field, o), r);
}

const char* stageName(ExportStage s) {
  switch (s) {
    case ExportStage::Bounds:
      return "bounds";
    case ExportStage::Mesh:
      return "meshing";
    case ExportStage::Check:
      return "checking";
    case ExportStage::Write:
      return "writing";
  }
  return "?";
}

ExportResult exportField(const Field& field, const ExportRequest& request, const std::string& path,
                         const std::string& name) {
  using Clock = std::chrono::steady_clock;
  auto report = [&](ExportStage s, double f) {
    if (request.progress && !request.progress(s, f)) throw Cancelled();
  };
  auto since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  // The format and the settings first: bad ones are refused before any work.
  const MeshFormat format = request.format ? *request.format : formatFromPath(path);
  try {
    request.mesh.validate();
  } catch (const SettingError& e) {
    throw SettingError(e.option, name + ": " + e.templ);
  }
  ExportResult result;

  auto t = Clock::now();
  std::optional<Phase> phase(std::in_place, "export: the box", PhaseKind::Serial);
  report(ExportStage::Bounds, 0.0);
  try {
    result.box = chooseBox(field, request.known, request.box);
  } catch (const EmptySolidError& e) {
    throw EmptySolidError(name + ": " + e.what());
  } catch (const ModelError& e) {
    throw ModelError(name + ": " + e.what());
  }
  report(ExportStage::Bounds, 1.0);
  result.seconds[0] = since(t);

  t = Clock::now();
  phase.reset();
  MeshingOptions o;
  o.bbox = result.box.box;
  o.resolution = result.box.resolution;
  o.settings = request.mesh;
  // Vertex normals only where the file keeps them: STL's facet normals come from the
  // triangles, FreeCAD computes its own for .bms.
  o.normals = request.normals && (format == MeshFormat::Obj || format == MeshFormat::Ply);
  o.memoryBudget = request.memoryBudget ? *request.memoryBudget : availableMemory();
  o.bytesPerTriangle = kMesherBytesPerTriangle + (request.check ? kCheckBytesPerTriangle : 0.0);
  TriangleMesh mesh, unsimplified;
  try {
    FinishedMesh m = meshAndFinish(
        field, o,
        request.progress ? [&](double f) { return request.progress(ExportStage::Mesh, f); }
                         : std::function<bool(double)>(),
        request.check);
    mesh = std::move(m.mesh);
    unsimplified = std::move(m.meshers);
    result.stats = std::move(m.stats);
    result.straightened = m.straightened;
    result.straighten = m.straighten;
    result.simplified = m.simplified;
    result.simplify = m.simplify;
  } catch (const TooLargeError& e) {
    throw TooLargeError(name + ": " + e.what());
  } catch (const ModelError& e) {
    throw ModelError(name + ": " + e.what());
  }
  result.triangles = mesh.triangleCount();
  result.seconds[1] = since(t);

  // The file is written while the check runs, under its temporary name, on a thread of its
  // own (writing is mostly handing pages to the file system): the check's verdict decides
  // whether it is renamed into place, and a refusal or a cancel removes it.
  using Pending = std::unique_ptr<AtomicFile>;
  Pending pending;
  std::future<Pending> writing;
  struct Join {  // the writer reads `mesh`: wait for it before anything changes or unwinds
    std::future<Pending>& f;
    ~Join() {
      if (!f.valid()) return;
      try {
        f.get();  // (and the temporary file is removed)
      } catch (...) {
      }
    }
  } join{writing};
  // A 3MF is one object, named as asked, and holds every coordinate exactly
  // (io/three_mf_stream.h): the check of the mesh is the check of the file.
  const std::string objectName =
      request.objectName.empty() ? fs::path(path).stem().string() : request.objectName;
  auto writeUncommitted = [&mesh, &path, &request, format,
                           objectName](const WriteProgress& progress) -> Pending {
    if (format != MeshFormat::ThreeMf) return writeMeshUncommitted(mesh, path, format, progress);
    ThreeMfOptions threeMf = request.threeMf;
    threeMf.validate = false;  // the check is the judge (stricter than lib3mf's rule)
    return write3mfUncommitted({{objectName, mesh}}, path, threeMf, progress);
  };
  if (request.check)
    writing = std::async(std::launch::async, [&writeUncommitted] { return writeUncommitted({}); });

  if (request.check) {
    t = Clock::now();
    report(ExportStage::Check, 0.0);
    result.report = checkMesh(mesh, [&](double f) {
      // The check cannot stop inside CGAL; a cancel asked for meanwhile is honoured at the
      // next phase, before anything is written.
      report(ExportStage::Check, f);
    });
    phase.emplace("export: waiting for the file", PhaseKind::Serial);
    if (writing.valid()) pending = writing.get();  // (a write error is thrown here)
    phase.reset();
    // Every collapse was proved safe, so a refused simplification is a bug; the mesher's
    // own mesh is checked then and written if printable, and the result says so.
    if (!result.report.printable() && (result.simplified || result.straightened)) {
      CheckReport original = checkMesh(unsimplified);  // (progress stays at the end)
      if (original.printable()) {
        pending.reset();  // (the file holds the refused mesh)
        mesh = std::move(unsimplified);
        result.triangles = mesh.triangleCount();
        result.report = std::move(original);
        result.simplified = false;
        result.straightened = false;
        result.simplificationRefused = true;
      }
    }
    unsimplified = TriangleMesh();
    result.checked = true;
    result.seconds[2] = since(t);
    if (!result.report.printable() && !request.force) return result;
  }
  if (request.stats) {
    AccuracyOptions a;
    a.bbox = result.box.box;
    a.cell = result.box.resolution;
    result.accuracy = measureAccuracy(mesh, field, a);
  }

  t = Clock::now();
  phase.emplace("export: writing", PhaseKind::Serial);
  report(ExportStage::Write, 0.0);
  if (!pending)  // (no check, or the mesh changed after a refused simplification)
    pending = writeUncommitted(
        [&](double f) { return !request.progress || request.progress(ExportStage::Write, f); });
  pending->commit();
  result.written = true;
  result.seconds[3] = since(t);
  report(ExportStage::Write, 1.0);
  return result;
}

ThreeMfExportResult export3mf(const std::vector<NamedMesh>& objects, const ThreeMfOptions& options,
                              const std::string& path, bool force,
                              const std::function<bool(double)>& progress) {
  // the checks 70 % of the bar (each object by its triangles), the writing the rest
  const Progress bar(progress);
  const std::vector<Progress> phase = bar.phases({0.7, 0.3});
  ThreeMfOptions o = options;
  o.validate = false;  // the check below judges, with every reason, not only the first
  ThreeMfExportResult result;
  std::size_t total = 0, done = 0;
  for (const NamedMesh& m : objects) total += m.mesh.triangles.size();
  const double all = double(std::max<std::size_t>(total, 1));
  for (const NamedMesh& m : objects) {
    const Progress object = phase[0].sub(double(done) / all, double(m.mesh.triangles.size()) / all);
    result.reports.push_back(checkMesh(m.mesh, [&object](double f) { object.step(f); }));
    done += m.mesh.triangles.size();
  }
  if (!result.printable() && !force) return result;
  // the package holds the objects exactly (io/three_mf_stream.h): what was checked is written
  write3mfUncommitted(objects, path, o, phase[1].callback())->commit();
  result.written = true;
  bar.step(1.0);
  return result;
}

}  // namespace frep

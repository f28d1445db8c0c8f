// The whole default export beside the dense OpenVDB route's meshing, per reference model, at N
// cells across the longest side and T threads: BM_Export/csg/256/2 and
// BM_OpenVdbRoute/csg/256/2 side by side in one run (bench/peer_figures.sh makes the table).
//   BM_Export        what `frepcad export MODEL.json -o MODEL.stl --cells N` does: mesh with
//                    the default settings, the CGAL check, the STL written (to /dev/shm when
//                    it exists, so the disk's speed is not measured)
//   BM_OpenVdbRoute  what OpenVDB offers for a function: every grid point evaluated (our
//                    batches, in parallel over x slabs) into a tools::Dense grid, values
//                    clamped to a band of 3 voxels and copied to a sparse grid, then
//                    tools::volumeToMesh at 0; its triangles count each quad as two
#include <benchmark/benchmark.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "dense_route.h"
#include "frep/model_json.h"
#include "pipeline/export_pipeline.h"
#include "volume/openvdb_grids.h"

namespace frep {
namespace {

struct Reference {
  Program program;
  Box3 box;
  double cell = 0.0;
};

Reference reference(const std::string& name, long cells) {
  const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/" + name + ".json");
  Reference r{compile(m.root), *m.bbox};
  double longest = 0.0;
  for (int a = 0; a < 3; ++a) longest = std::max(longest, r.box.hi[a] - r.box.lo[a]);
  r.cell = longest / static_cast<double>(cells);
  return r;
}

std::string scratchFile(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
  return (dir / ("frepcad-bench-" + std::to_string(getpid()) + "-" + name + ".stl")).string();
}

void exportReference(benchmark::State& state, const std::string& name) {
  const Reference r = reference(name, state.range(0));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(state.range(1)));
  ExportRequest request;
  request.box.bbox = r.box;
  request.box.resolution = r.cell;
  const std::string path = scratchFile(name);
  ExportResult result;
  double mesh = 0.0, check = 0.0;
  for (auto _ : state) {
    result = exportField(r.program, request, path, name);
    mesh += result.seconds[1];
    check += result.seconds[2];
  }
  std::filesystem::remove(path);
  const double n = static_cast<double>(state.iterations());
  state.counters["triangles"] = static_cast<double>(result.triangles);
  state.counters["mesh_s"] = mesh / n;
  state.counters["check_s"] = check / n;
  state.counters["printable"] = result.report.printable() ? 1.0 : 0.0;
}

void openVdbRoute(benchmark::State& state, const std::string& name) {
  initializeOpenVdb();
  const Reference r = reference(name, state.range(0));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(state.range(1)));
  const double h = r.cell;
  // The box's grid points and one layer beyond it, so a solid the box cuts is closed.
  openvdb::Coord lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = static_cast<int>(std::floor(r.box.lo[a] / h)) - 1;
    hi[a] = static_cast<int>(std::ceil(r.box.hi[a] / h)) + 1;
  }
  std::size_t triangles = 0;
  for (auto _ : state) {
    const openvdb::FloatGrid::Ptr grid = bench::denseLevelSet(r.program, lo, hi, h);
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> tris;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*grid, points, tris, quads, 0.0, 0.0);
    triangles = tris.size() + 2 * quads.size();
    benchmark::DoNotOptimize(points.data());
  }
  state.counters["triangles"] = static_cast<double>(triangles);
}

const bool kPeerBenchmarks = [] {
  for (const char* model : {"sphere", "csg", "twist", "helix", "gyroid"}) {
    const std::string m = model;
    benchmark::RegisterBenchmark(("BM_Export/" + m).c_str(),
                                 [m](benchmark::State& s) { exportReference(s, m); })
        ->ArgsProduct({{256, 512}, {1, 2}})
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    benchmark::RegisterBenchmark(("BM_OpenVdbRoute/" + m).c_str(),
                                 [m](benchmark::State& s) { openVdbRoute(s, m); })
        ->ArgsProduct({{256, 512}, {1, 2}})
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  return true;
}();

}  // namespace
}  // namespace frep

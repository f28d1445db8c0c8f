// Loads mesh_sdf and vdb_grid nodes' files into fields, once per file version, and builds
// voronoi_foam nodes' networks, once per parameters: a loaded field
// is kept while anything uses it and the last few stay cached, keyed by the path, the file's
// size and modification time and the node's parameters, so compiling a tree and bounding it
// (and recomputing a document) reads a file once.
#include "volume/field_sources.h"

#include <sys/stat.h>

#include <limits>
#include <list>
#include <map>
#include <mutex>
#include <sstream>

#include "base/errors.h"
#include "base/file_names.h"
#include "frep/field_sources.h"
#include "io/mesh_io.h"
#include "volume/grid_field.h"
#include "volume/level_sets.h"
#include "volume/mesh_distance.h"
#include "volume/voronoi_foam.h"

namespace frep {

namespace {

constexpr std::size_t kKeptFields = 4;

class FieldCache {
 public:
  template <class Load>
  std::shared_ptr<const Field> get(const std::string& key, Load load) {
    {
      std::lock_guard<std::mutex> lock(m_);
      auto it = live_.find(key);
      if (it != live_.end())
        if (auto f = it->second.lock()) {
          keep(f);
          return f;
        }
    }
    // Loading runs unlocked: another file can load meanwhile (the same one may load twice).
    std::shared_ptr<const Field> f = load();
    std::lock_guard<std::mutex> lock(m_);
    live_[key] = f;
    keep(f);
    return f;
  }

 private:
  void keep(const std::shared_ptr<const Field>& f) {
    kept_.remove(f);
    kept_.push_front(f);
    while (kept_.size() > kKeptFields) kept_.pop_back();
  }
  std::mutex m_;
  std::map<std::string, std::weak_ptr<const Field>> live_;
  std::list<std::shared_ptr<const Field>> kept_;
};

FieldCache& cache() {
  static FieldCache c;
  return c;
}

// The node's type and every parameter's value, exactly.
std::string paramsKey(const Node& n) {
  std::ostringstream key;
  key.precision(17);
  key << n.type->id;
  for (const auto& [name, v] : n.params) {
    key << '\n' << name << '=' << v.text;
    for (double x : v.numbers) key << ' ' << x;
  }
  return key.str();
}

// ... and the file's version.
std::string fileKey(const Node& n) {
  const std::string& path = n.param("path").text;
  requireRegularFile(path, n.type->id == "vdb_grid" ? "the OpenVDB file" : "the mesh file");
  struct stat st {};
  ::stat(path.c_str(), &st);
  std::ostringstream key;
  key << paramsKey(n) << '\n'
      << st.st_size << '\n'
      << st.st_mtim.tv_sec << '.' << st.st_mtim.tv_nsec;
  return key.str();
}

// A foam is built once per parameters: compiling a tree and bounding it, and every recompute
// of a document, find it here.
std::shared_ptr<const Field> loadVoronoiFoam(const Node& n) {
  return cache().get(paramsKey(n), [&] { return makeVoronoiFoam(voronoiFoamSettings(n)); });
}

std::shared_ptr<const Field> loadMeshSdf(const Node& n) {
  return cache().get(fileKey(n), [&] {
    const std::string& path = n.param("path").text;
    const TriangleMesh mesh = readMesh(path);
    const MeshFieldMethod method =
        n.param("method").text == "grid" ? MeshFieldMethod::Grid : MeshFieldMethod::Exact;
    return meshField(mesh, method, n.real("voxel"), "mesh_sdf '" + displayName(path) + "'");
  });
}

std::shared_ptr<const Field> loadVdbGrid(const Node& n) {
  return cache().get(fileKey(n), [&] {
    const std::string& path = n.param("path").text;
    const std::string where = "vdb_grid '" + displayName(path) + "'";
    const GridSet grids = readVdb(path);
    const std::size_t index = grids.scalarGrid(n.param("grid").text, where);
    GridFieldOptions o;
    o.interpolation = n.param("interpolation").text == "quadratic" ? GridInterpolation::Quadratic
                                                                   : GridInterpolation::Linear;
    o.iso = n.real("iso");
    return gridField(grids, index, o, where);
  });
}

}  // namespace

std::shared_ptr<const Field> meshField(const TriangleMesh& mesh, MeshFieldMethod method,
                                       double voxel, const std::string& where) {
  if (method == MeshFieldMethod::Exact) return meshDistanceField(mesh, where);
  LevelSetOptions o;
  o.voxel = voxel;
  // Distances all through the inside: a shell or an infill of the solid reaches deeper than
  // a narrow band (whose constant beyond would make the shell solid).
  o.interiorWidthVoxels = std::numeric_limits<double>::infinity();
  if (o.voxel <= 0.0) {
    double side = 0.0;
    if (!mesh.positions.empty()) {
      Vec3f lo = mesh.positions[0], hi = lo;
      for (const Vec3f& p : mesh.positions)
        for (int a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], p[a]);
          hi[a] = std::max(hi[a], p[a]);
        }
      for (int a = 0; a < 3; ++a) side = std::max(side, double(hi[a]) - lo[a]);
    }
    o.voxel = side > 0 ? side / 256.0 : 1.0;
  }
  const GridSet grids = meshToLevelSet(mesh, o, where);
  return gridField(grids, 0, GridFieldOptions{}, where);
}

void registerVolumeSources() {
  static std::once_flag once;
  std::call_once(once, [] {
    setFieldSourceLoader("mesh_sdf", loadMeshSdf);
    setFieldSourceLoader("vdb_grid", loadVdbGrid);
    setFieldSourceLoader("voronoi_foam", loadVoronoiFoam);
  });
}

}  // namespace frep

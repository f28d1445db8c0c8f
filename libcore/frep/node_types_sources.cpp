// Fields read from files (see field_sources.h): a triangle mesh's signed distance and an
// OpenVDB grid. Each compiles to one `external` instruction holding the loaded field.
#include <map>
#include <mutex>

#include "base/errors.h"
#include "frep/field_sources.h"
#include "frep/registry.h"
#include "frep/tree.h"

namespace frep {

namespace {

std::mutex& loadersMutex() {
  static std::mutex m;
  return m;
}

std::map<std::string, FieldSourceLoader>& loaders() {
  static std::map<std::string, FieldSourceLoader> table;
  return table;
}

Slot compileSource(CompileContext& c) {
  return c.b.external(loadFieldSource(c.node()), c.p.x, c.p.y, c.p.z);
}

Box3 sourceBounds(const Node& n, const std::vector<Box3>&) { return loadFieldSource(n)->bounds(); }

}  // namespace

void setFieldSourceLoader(const std::string& typeId, FieldSourceLoader loader) {
  std::lock_guard<std::mutex> lock(loadersMutex());
  loaders()[typeId] = std::move(loader);
}

std::shared_ptr<const Field> loadFieldSource(const Node& node) {
  FieldSourceLoader loader;
  {
    std::lock_guard<std::mutex> lock(loadersMutex());
    auto it = loaders().find(node.type->id);
    if (it != loaders().end()) loader = it->second;
  }
  if (!loader)
    throw ModelError(node.type->id + ": this program was built without the volume library "
                     "that reads these files (frepcad, frepcore and the workbench have it)");
  return loader(node);
}

void registerFieldSources(Registry& r) {
  {
    ParamTemplate voxel = realParam(
        "voxel", 0.0, "length",
        "Voxel size of the level set for method 'grid'; 0 chooses 1/256 of the mesh's largest "
        "side.");
    range(voxel, 0.0, std::numeric_limits<double>::infinity());
    r.add({"mesh_sdf",
           "field source",
           "A closed triangle mesh (STL, OBJ, PLY or 3MF file) as a solid: its signed distance, "
           "positive inside. Method 'exact' measures the distance to the triangles themselves "
           "(CGAL AABB tree, ray-cast inside test), so the solid is the mesh at any resolution; "
           "method 'grid' samples it once into an OpenVDB level set (meshToLevelSet) at the "
           "voxel size and interpolates, which is faster to evaluate and also accepts "
           "self-intersecting meshes (its distances fill the whole inside, and reach 3 voxels "
           "outside). Open or non-manifold meshes are refused with the count of their border "
           "or non-manifold edges.",
           "F = +distance to the mesh inside, -distance outside",
           0,
           0,
           {fileParam("path", "The mesh file (.stl, .obj, .ply, .off, .3mf)."),
            choiceParam("method", {"exact", "grid"},
                        "'exact': distance to the triangles; 'grid': an OpenVDB level set."),
            voxel},
           compileSource,
           sourceBounds});
  }
  {
    ParamTemplate iso = realParam("iso", 0.0, "",
                                  "The grid value on the surface (0 for a level set; for a fog "
                                  "volume e.g. 0.5).");
    r.add({"vdb_grid",
           "field source",
           "A float or double grid of an OpenVDB (.vdb) file as a solid. A level set (grid "
           "class level set: negative inside) is inside where its value is below `iso`; any "
           "other grid (a fog volume) is inside where its value is above `iso`. Values between "
           "voxels are interpolated as OpenVDB's BoxSampler (trilinear) or QuadraticSampler "
           "(triquadratic) do; interval bounds come from the grid's tree (the minimum and "
           "maximum of every node), so empty space is pruned. Beyond a level set's narrow band "
           "the value is its background (constant): a shell or offset deeper than the band "
           "needs a grid with a wider one.",
           "F = iso - v (level set) or v - iso (other grids), v interpolated",
           0,
           0,
           {fileParam("path", "The OpenVDB file (.vdb)."),
            textParam("grid", "",
                      "The grid's name in the file; empty: the first float or double grid."),
            choiceParam("interpolation", {"linear", "quadratic"},
                        "'linear': trilinear (BoxSampler); 'quadratic': triquadratic "
                        "(QuadraticSampler)."),
            iso},
           compileSource,
           sourceBounds});
  }
}

}  // namespace frep

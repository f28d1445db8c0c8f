// volume/: meshes and OpenVDB grids as fields (mesh_sdf, vdb_grid), level sets from fields and
// meshes, meshes from level sets, and .vdb files.
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <mutex>
#include <random>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "frep/model_json.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"
#include "lattice/ffd_map.h"
#include "lattice_samples.h"
#include "mesh/mesher.h"
#include "volume/field_sources.h"
#include "volume/grid_ffd.h"
#include "volume/grid_field.h"
#include "volume/level_sets.h"
#include "volume/mesh_distance.h"
#include "volume/openvdb_grids.h"
#include "volume_samples.h"

namespace frep {
namespace {

using testing::icosphere;
using testing::sampleFolder;

double norm3(double x, double y, double z) {
  return std::sqrt(x * x + y * y + z * z);
}

// How far the icosphere's triangles come inside the unit sphere: its vertices lie on the
// sphere, so this is the largest gap between the two surfaces (the tessellation error).
double inscribedGap(const TriangleMesh& m) {
  double gap = 0;
  for (const Triangle& t : m.triangles) {
    double c[3] = {0, 0, 0};
    for (std::uint32_t v : t)
      for (int a = 0; a < 3; ++a) c[a] += m.positions[v][a] / 3.0;
    gap = std::max(
        gap,
        1.0 - norm3(c[0], c[1], c[2]));  // the centroid is the face's nearest point to the centre
  }
  return gap;
}

std::string writeSample(const TriangleMesh& m, const std::string& name) {
  const std::string path = sampleFolder() + "/" + name;
  writeMesh(m, path, MeshFormat::StlBinary);
  return path;
}

NodePtr meshSdf(const std::string& path, const std::string& method = "exact", double voxel = 0) {
  registerVolumeSources();
  return makeNode(
      "mesh_sdf",
      {{"path", textValue(path)}, {"method", choiceValue(method)}, {"voxel", realValue(voxel)}},
      {});
}

TEST(MeshSdf, SphereFromAnStlIsTheSphereWithinTheTessellationErrorInAllFourModes) {
  const TriangleMesh ico = icosphere(1.0, 3);
  const double gap = inscribedGap(ico);
  ASSERT_GT(gap, 1e-3);  // a real tessellation error, not zero
  for (const std::string method : {"exact", "grid"}) {
    const Program f = compile(meshSdf(writeSample(ico, "sphere3.stl"), method, 0.02));
    // The grid adds its interpolation error: a voxel's worth, far less in practice.
    const double tol = gap + (method == "grid" ? 0.02 : 0.0) + 1e-5;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    std::vector<double> x(10000), y(10000), z(10000), batch(10000);
    for (int i = 0; i < 10000; ++i) x[i] = u(rng), y[i] = u(rng), z[i] = u(rng);
    f.evalBatch(x.data(), y.data(), z.data(), x.size(), batch.data());
    double worst = 0;
    int gradientsChecked = 0;
    for (int i = 0; i < 10000; ++i) {
      const double r = norm3(x[i], y[i], z[i]), exact = 1.0 - r;
      const double v = f.eval(x[i], y[i], z[i]);
      ASSERT_EQ(v, batch[i]) << "point and batch differ";
      // The grid's narrow band holds distances only near the surface; beyond, its sign.
      if (method == "grid" && std::abs(exact) > 0.05) {
        ASSERT_EQ(v > 0, exact > 0) << method << " at r = " << r;
        continue;
      }
      worst = std::max(worst, std::abs(v - exact));
      const Dual g = f.evalGradient(x[i], y[i], z[i]);
      ASSERT_EQ(g.v, v);
      if (std::abs(exact) > 0.2 && method == "exact") {
        // Away from the surface the nearest point is near the radial one: -p/|p|.
        const double dotp = -(g.d[0] * x[i] + g.d[1] * y[i] + g.d[2] * z[i]) / r;
        EXPECT_GT(dotp, 0.99) << "gradient at r = " << r;
        ++gradientsChecked;
      }
      if (i % 50 == 0) {
        const double h = 0.05;
        const Interval iv =
            f.evalInterval({x[i] - h, x[i] + h}, {y[i] - h, y[i] + h}, {z[i] - h, z[i] + h});
        ASSERT_TRUE(iv.contains(v));
        for (int k = 0; k < 8; ++k)
          ASSERT_TRUE(iv.contains(
              f.eval(x[i] + (k & 1 ? h : -h), y[i] + (k & 2 ? h : -h), z[i] + (k & 4 ? h : -h))));
      }
    }
    EXPECT_LE(worst, tol) << method;
    if (method == "exact") {
      EXPECT_GT(gradientsChecked, 3000);
    }
  }
}

TEST(MeshSdf, OpenNonManifoldAndSelfIntersectingMeshesAreRefusedWithTheReason) {
  TriangleMesh open = icosphere(1.0, 1);
  open.triangles.pop_back();
  try {
    compile(meshSdf(writeSample(open, "open.stl")));
    FAIL() << "an open mesh was accepted";
  } catch (const FileError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("open.stl"), std::string::npos) << what;
    EXPECT_NE(what.find("3 border edges"), std::string::npos) << what;
  }
  EXPECT_THROW(compile(meshSdf(writeSample(open, "open2.stl"), "grid", 0.05)), FileError);

  // Two overlapping spheres: the exact inside test refuses, OpenVDB's flood fill resolves it.
  TriangleMesh two = icosphere(1.0, 2), other = icosphere(1.0, 2);
  const auto base = static_cast<std::uint32_t>(two.positions.size());
  for (auto p : other.positions) two.positions.push_back({p[0] + 0.8f, p[1], p[2]});
  for (auto t : other.triangles) two.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  const std::string path = writeSample(two, "overlap.stl");
  try {
    compile(meshSdf(path));
    FAIL() << "a self-intersecting mesh was accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("method 'grid'"), std::string::npos) << e.what();
  }
  const Program g = compile(meshSdf(path, "grid", 0.05));
  EXPECT_GT(g.eval(0.4, 0, 0), 0.1);  // inside both: inside the union (beyond the band)
  EXPECT_LT(g.eval(0.4, 1.2, 0), 0);

  // Inward-facing triangles give the same solid.
  TriangleMesh flipped = icosphere(1.0, 2);
  for (Triangle& t : flipped.triangles) std::swap(t[1], t[2]);
  const Program a = compile(meshSdf(writeSample(flipped, "flipped.stl")));
  EXPECT_NEAR(a.eval(0, 0, 0), 1.0, 0.05);
  EXPECT_NEAR(a.eval(2, 0, 0), -1.0, 0.05);
}

TEST(MeshSdf, ARelativePathInAModelFileIsReadFromTheModelsFolder) {
  const std::string folder = sampleFolder() + "/models";
  ASSERT_EQ(std::system(("mkdir -p '" + folder + "'").c_str()), 0);
  writeMesh(icosphere(1.0, 2), folder + "/part.stl", MeshFormat::StlBinary);
  std::ofstream(folder + "/model.json")
      << R"({"root": {"type": "offset", "params": {"distance": 0.25},
             "inputs": [{"type": "mesh_sdf", "params": {"path": "part.stl"}}]}})";
  registerVolumeSources();
  const Model m = loadModel(folder + "/model.json");
  const Program p = compile(m.root);
  EXPECT_NEAR(p.eval(1.2, 0, 0), 0.05, 0.02);
  // The mesh's box is the node's structural bounds (an offset widens it).
  const Box3 b = structuralBounds(m.root->inputs[0]);
  EXPECT_NEAR(b.hi[0], 1.0, 1e-6);
  // A missing file names itself.
  try {
    compile(meshSdf(folder + "/missing.stl"));
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.stl"), std::string::npos) << e.what();
  }
}

// ---- grids ----

GridSet sampledSphere(double voxel, double radius = 1.0) {
  LevelSetOptions o;
  o.voxel = voxel;
  const Program s = compile(testing::sphereNode(radius));
  const double e = radius + 0.2;
  return sampleLevelSet(s, Box3{{-e, -e, -e}, {e, e, e}}, o);
}

TEST(GridField, IntervalsEncloseEverySampledValueForBothInterpolations) {
  const GridSet grids = sampledSphere(0.1);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> c(-1.6, 1.6), h(0.0, 0.4);
  for (const auto interp : {GridInterpolation::Linear, GridInterpolation::Quadratic}) {
    GridFieldOptions o;
    o.interpolation = interp;
    const auto f = gridField(grids, 0, o, "sphere");
    int tight = 0;
    for (int b = 0; b < 400; ++b) {
      const double cx = c(rng), cy = c(rng), cz = c(rng), hx = h(rng), hy = h(rng), hz = h(rng);
      const Interval iv =
          f->evalInterval({cx - hx, cx + hx}, {cy - hy, cy + hy}, {cz - hz, cz + hz});
      std::uniform_real_distribution<double> ux(cx - hx, cx + hx), uy(cy - hy, cy + hy),
          uz(cz - hz, cz + hz);
      for (int s = 0; s < 60; ++s) {
        const double x = s < 8 ? cx + (s & 1 ? hx : -hx) : ux(rng);
        const double y = s < 8 ? cy + (s & 2 ? hy : -hy) : uy(rng);
        const double z = s < 8 ? cz + (s & 4 ? hz : -hz) : uz(rng);
        const double v = f->eval(x, y, z);
        ASSERT_TRUE(iv.contains(v)) << v << " outside [" << iv.lo << ", " << iv.hi << "]";
      }
      tight += iv.width() < 1.0;
    }
    // Bounds from the tree's extrema, not "anything": most boxes get a useful width.
    EXPECT_GT(tight, 200);
  }
  // Far from the sphere the background alone: the interval is one value.
  const auto f = gridField(grids, 0, GridFieldOptions{}, "sphere");
  const Interval far = f->evalInterval({50, 60}, {50, 60}, {-5, 5});
  EXPECT_LT(far.hi, 0.0);
  EXPECT_NEAR(far.width(), 0.0, 1e-9);
  const Interval all = f->evalInterval(Interval::entire(), Interval::entire(), Interval::entire());
  EXPECT_GT(all.hi, 0.0);
  EXPECT_LT(all.lo, 0.0);
  // The solid's box comes from the tree: the sphere's, within the band and the stencil.
  const Box3 b = f->bounds();
  for (int a = 0; a < 3; ++a) {
    EXPECT_LT(b.lo[a], -1.0);
    EXPECT_GT(b.lo[a], -2.1);
    EXPECT_GT(b.hi[a], 1.0);
    EXPECT_LT(b.hi[a], 2.1);
  }
}

// A field that counts the points it is asked for.
class CountingField final : public Field {
 public:
  explicit CountingField(const Field& f) : f_(f) {}
  double eval(double x, double y, double z) const override {
    ++points;
    return f_.eval(x, y, z);
  }
  void evalBatch(const double* x, const double* y, const double* z, std::size_t n,
                 double* out) const override {
    points += n;
    f_.evalBatch(x, y, z, n, out);
  }
  Interval evalInterval(const Interval& x, const Interval& y, const Interval& z) const override {
    return f_.evalInterval(x, y, z);
  }
  Dual evalGradient(const Dual& x, const Dual& y, const Dual& z) const override {
    ++points;
    return f_.evalGradient(x, y, z);
  }
  void evalGradientBatch(const Dual* x, const Dual* y, const Dual* z, std::size_t n,
                         Dual* out) const override {
    points += n;
    f_.evalGradientBatch(x, y, z, n, out);
  }
  using Field::evalGradient;
  mutable std::atomic<std::size_t> points{0};

 private:
  const Field& f_;
};

TEST(LevelSet, SamplingSkipsEmptySpaceAndItsMeshesArePrintable) {
  // A small csg part (the cube [0, 1.6]^3 less the unit ball) in a large box: only the blocks
  // near its surface are evaluated.
  const NodePtr part = makeNode(
      "difference", {},
      {makeNode("box", {{"size", vec3Value({1.6, 1.6, 1.6})}}, {}), testing::sphereNode(1.0)});
  const Program p = compile(part);
  CountingField counted(p);
  LevelSetOptions o;
  o.voxel = 0.04;
  const Box3 box{{-4, -4, -4}, {4, 4, 4}};
  const GridSet grids = sampleLevelSet(counted, box, o);
  const double allVoxels = std::pow(8.0 / 0.04, 3);
  EXPECT_LT(double(counted.points), 0.05 * allVoxels) << counted.points;
  EXPECT_GT(counted.points.load(), 0u);
  const GridInfo info = grids.info(0);
  EXPECT_EQ(info.gridClass, "level set");
  EXPECT_EQ(info.valueType, "float");

  // OpenVDB's volumeToMesh of the level set, judged by the check.
  const TriangleMesh viaVdb = levelSetToMesh(grids, 0);
  const CheckReport r = checkMesh(viaVdb);
  EXPECT_TRUE(r.printable()) << reportToText(r, "volumeToMesh");
  const double exact = 1.6 * 1.6 * 1.6 - M_PI / 6;  // the cube less the ball's octant
  EXPECT_NEAR(r.volume, exact, 0.02 * exact);

  // The grid as a field, meshed by the mesher: printable too, and the same volume.
  const auto f = gridField(grids, 0, GridFieldOptions{}, "part");
  MeshingOptions m;
  m.bbox = f->bounds();
  m.resolution = 0.04;
  const CheckReport mine = checkMesh(polygonize(*f, m));
  EXPECT_TRUE(mine.printable()) << reportToText(mine, "mesher");
  EXPECT_NEAR(mine.volume, r.volume, 0.03 * r.volume);
  // And close to the exact part's volume, meshed from its function.
  EXPECT_NEAR(mine.volume, exact, 0.02 * exact);
}

TEST(LevelSet, SamplingReportsProgressAndCancels) {
  const Program p = compile(testing::sphereNode(1.0));
  LevelSetOptions o;
  o.voxel = 0.02;
  std::vector<double> seen;
  std::mutex m;
  o.progress = [&](double f) {
    std::lock_guard<std::mutex> lock(m);
    seen.push_back(f);
    return true;
  };
  sampleLevelSet(p, Box3{{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}}, o);
  ASSERT_GT(seen.size(), 3u);
  EXPECT_EQ(seen.back(), 1.0);
  int calls = 0;
  o.progress = [&](double) { return ++calls < 2; };
  EXPECT_THROW(sampleLevelSet(p, Box3{{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}}, o), Cancelled);
}

TEST(LevelSet, AClosedMeshBecomesALevelSetAndAnOpenOneIsRefused) {
  LevelSetOptions o;
  o.voxel = 0.05;
  const GridSet g = meshToLevelSet(icosphere(1.0, 3), o, "ico");
  const auto f = gridField(g, 0, GridFieldOptions{}, "ico");
  EXPECT_NEAR(f->eval(0.9, 0, 0), 0.1, 0.03);
  EXPECT_NEAR(f->eval(0, -1.1, 0), -0.1, 0.03);
  EXPECT_GT(f->eval(0, 0, 0), 0);  // deep inside: the inside tiles
  TriangleMesh open = icosphere(1.0, 2);
  open.triangles.resize(open.triangles.size() / 2);
  EXPECT_THROW(meshToLevelSet(open, o, "half"), FileError);
  o.voxel = -1;
  EXPECT_THROW(meshToLevelSet(icosphere(1.0, 1), o, "ico"), ModelError);
}

// ---- .vdb files ----

template <class GridT>
typename GridT::Ptr filledGrid(const std::string& name, typename GridT::ValueType a,
                               typename GridT::ValueType b) {
  auto g = GridT::create(a);
  g->setName(name);
  g->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
  auto acc = g->getAccessor();
  for (int i = -20; i < 20; i += 3)
    for (int j = -5; j < 30; j += 2)
      acc.setValue(openvdb::Coord(i, j, i * j % 7), (i + j) % 2 ? a : b);
  acc.setValueOff(openvdb::Coord(100, 100, 100), b);  // an inactive voxel with its own value
  g->insertMeta("author", openvdb::StringMetadata("frep test"));
  g->insertMeta("weight", openvdb::FloatMetadata(2.5f));
  return g;
}

template <class GridT>
bool identical(const openvdb::GridBase& x, const openvdb::GridBase& y) {
  const auto& a = static_cast<const GridT&>(x);
  const auto& b = static_cast<const GridT&>(y);
  if (!a.tree().hasSameTopology(b.tree()) || !(a.background() == b.background())) return false;
  if (a.transform() != b.transform() || a.getGridClass() != b.getGridClass()) return false;
  for (auto it = a.tree().cbeginValueAll(); it; ++it) {
    typename GridT::ValueType v;
    b.tree().probeValue(it.getCoord(), v);
    if (!(v == *it)) return false;
  }
  return true;
}

TEST(VdbFiles, ARoundTripKeepsEveryGridBitIdentical) {
  initializeOpenVdb();
  openvdb::GridPtrVec grids;
  grids.push_back(filledGrid<openvdb::FloatGrid>("density", 0.5f, -1.25f));
  grids.push_back(filledGrid<openvdb::DoubleGrid>("temperature", 1e-300, 3.14159265358979));
  grids.push_back(filledGrid<openvdb::Int32Grid>("label", 7, -123456));
  grids.push_back(filledGrid<openvdb::BoolGrid>("mask", false, true));
  grids.push_back(filledGrid<openvdb::Vec3SGrid>("velocity", openvdb::Vec3s(1, 2, 3),
                                                 openvdb::Vec3s(-0.5f, 0, 1e-7f)));
  grids.push_back(sampledSphere(0.1).impl->grids[0]);
  const GridSet set = gridSetOf(grids);
  const std::string path = sampleFolder() + "/round.vdb";
  writeVdb(set, path);
  const GridSet back = readVdb(path);
  ASSERT_EQ(back.size(), set.size());
  for (std::size_t i = 0; i < set.size(); ++i) {
    // (A file keeps grids by name, not necessarily in their order.)
    std::size_t j = 0;
    while (j < back.size() && back.info(j).name != set.info(i).name) ++j;
    ASSERT_LT(j, back.size()) << set.info(i).name << " is missing";
    const GridInfo a = set.info(i), b = back.info(j);
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.valueType, b.valueType);
    EXPECT_EQ(a.gridClass, b.gridClass);
    EXPECT_EQ(a.activeVoxels, b.activeVoxels);
    EXPECT_EQ(b.metadata.count("file_voxel_count"), 1u);
    for (const auto& [k, v] : a.metadata) EXPECT_EQ(b.metadata.at(k), v) << a.name << " " << k;
    const openvdb::GridBase& x = *set.impl->grids[i];
    const openvdb::GridBase& y = *back.impl->grids[j];
    bool same = false;
    if (x.isType<openvdb::FloatGrid>()) same = identical<openvdb::FloatGrid>(x, y);
    if (x.isType<openvdb::DoubleGrid>()) same = identical<openvdb::DoubleGrid>(x, y);
    if (x.isType<openvdb::Int32Grid>()) same = identical<openvdb::Int32Grid>(x, y);
    if (x.isType<openvdb::BoolGrid>()) same = identical<openvdb::BoolGrid>(x, y);
    if (x.isType<openvdb::Vec3SGrid>()) same = identical<openvdb::Vec3SGrid>(x, y);
    EXPECT_TRUE(same) << a.name << " differs after the round trip";
  }
  EXPECT_EQ(describeGrid(set.info(0)).substr(0, 22), "grid 'density' (float,");
  // The scalar grids are fields; the others are refused by name, with the file's listing.
  EXPECT_EQ(back.info(back.scalarGrid("temperature", "f")).valueType, "double");
  EXPECT_TRUE(back.info(back.scalarGrid("", "f")).valueType == "float" ||
              back.info(back.scalarGrid("", "f")).valueType == "double");
  try {
    back.scalarGrid("label", "round.vdb");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("int32"), std::string::npos) << e.what();
  }
  try {
    back.scalarGrid("nothing", "round.vdb");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'velocity' (vec3s)"), std::string::npos) << e.what();
  }
}

TEST(VdbFiles, MalformedFilesGetClearErrorsAndHugeDeclaredGridsAreRefused) {
  const std::string folder = sampleFolder();
  auto errorOf = [](const std::string& path) -> std::string {
    try {
      readVdb(path);
    } catch (const FileError& e) {
      return e.what();
    }
    return "";
  };
  std::ofstream(folder + "/empty.vdb").close();
  std::ofstream(folder + "/text.vdb") << "this is not a volume\n";
  const std::string good = folder + "/good.vdb";
  writeVdb(sampledSphere(0.1), good);
  std::ifstream in(good, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::ofstream(folder + "/truncated.vdb", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  std::string flipped = bytes;
  for (std::size_t i = bytes.size() / 3; i < bytes.size(); i += 7) flipped[i] = char(~flipped[i]);
  std::ofstream(folder + "/corrupt.vdb", std::ios::binary) << flipped;
  for (const char* name : {"empty.vdb", "text.vdb", "truncated.vdb", "missing.vdb"}) {
    const std::string e = errorOf(folder + "/" + name);
    EXPECT_NE(e.find(name), std::string::npos) << name << ": " << e;
  }
  // Cut inside the header, or the magic number and noise: what is wrong, never "0 grids".
  for (std::size_t n : {4, 20, 40}) {
    const std::string name = "head" + std::to_string(n) + ".vdb";
    std::ofstream(folder + "/" + name, std::ios::binary) << bytes.substr(0, n);
    const std::string e = errorOf(folder + "/" + name);
    EXPECT_NE(e.find(n < 8 ? "no OpenVDB magic number" : "ends inside its header"),
              std::string::npos)
        << e;
  }
  std::string noise = bytes.substr(0, 8);
  for (int i = 0; i < 64; ++i) noise += char(37 * i + 11);
  std::ofstream(folder + "/noise.vdb", std::ios::binary) << noise;
  EXPECT_NE(errorOf(folder + "/noise.vdb").find("noise.vdb: "), std::string::npos);
  // A well-formed file of no grids holds nothing to read.
  writeVdb(GridSet(), folder + "/none.vdb");
  EXPECT_NE(errorOf(folder + "/none.vdb").find("holds no grids"), std::string::npos);

  // Corrupted compressed data: an error or (if OpenVDB cannot tell) some grid, never a crash.
  (void)errorOf(folder + "/corrupt.vdb");

  // A grid whose metadata declares more memory than allowed is refused before it is read.
  // (OpenVDB writes the true figure, so the file's bytes are changed: the int64 after the
  // name "file_mem_bytes", its type name and its 4-byte size.)
  std::string bomb = bytes;
  const std::size_t at = bomb.find("file_mem_bytes");
  ASSERT_NE(at, std::string::npos);
  const std::size_t type = bomb.find("int64", at);
  ASSERT_NE(type, std::string::npos);
  const std::int64_t huge = std::int64_t(1) << 40;
  std::memcpy(&bomb[type + 5 + 4], &huge, 8);
  std::ofstream(folder + "/bomb.vdb", std::ios::binary) << bomb;
  const std::string e = errorOf(folder + "/bomb.vdb");
  EXPECT_NE(e.find("bytes in memory"), std::string::npos) << e;
}

// A tree's topology starts with its buffer count (1), its background value and the root's
// tile and child counts: a count damaged to billions must end in an error at the file's end,
// not billions of reads past it.
TEST(VdbFiles, ADamagedTileCountEndsAtTheFileEndInsteadOfSpinning) {
  const std::string folder = sampleFolder();
  const float background = 1234.5f;
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(background);
  grid->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
  const std::string good = folder + "/tiles.vdb";
  writeVdb(gridSetOf({grid}), good);
  std::ifstream in(good, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  char head[8];
  const std::int32_t one = 1;
  std::memcpy(head, &one, 4);
  std::memcpy(head + 4, &background, 4);
  const std::size_t at = bytes.find(std::string(head, 8));
  ASSERT_NE(at, std::string::npos);
  const std::uint32_t tiles = 0xFFFFFF00u;
  std::memcpy(&bytes[at + 8], &tiles, 4);
  std::ofstream(folder + "/spinning.vdb", std::ios::binary) << bytes;
  try {
    readVdb(folder + "/spinning.vdb");
    ADD_FAILURE() << "a file declaring 4 billion tiles was read";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("spinning.vdb: the OpenVDB file ends inside its grids"),
              std::string::npos)
        << e.what();
  }
}

// OpenVDB fills a string of the length a file declares before it reads it: a name declared 4 GB
// long in a file of a few hundred bytes is refused from the file's size, before any of it is
// allocated (such files took 20 GB and a minute).
TEST(VdbFiles, ALengthPastTheFileEndIsRefusedBeforeOpenVdbAllocatesIt) {
  const std::string folder = sampleFolder();
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(1.0f);
  grid->tree().setValue(openvdb::Coord(1, 2, 3), 0.5f);
  grid->insertMeta("frepcad_marker", openvdb::StringMetadata("x"));
  const std::string good = folder + "/marked.vdb";
  writeVdb(gridSetOf({grid}), good);
  EXPECT_EQ(readVdb(good).size(), 1u);  // the check passes a sound file
  std::ifstream in(good, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  const std::size_t at = bytes.find("frepcad_marker");
  ASSERT_NE(at, std::string::npos);
  const std::uint32_t length = 0xF0000000u;
  std::memcpy(&bytes[at - 4], &length, 4);
  std::ofstream(folder + "/long_name.vdb", std::ios::binary) << bytes;
  try {
    readVdb(folder + "/long_name.vdb");
    ADD_FAILURE() << "a file declaring a 4 GB name was read";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("long_name.vdb: the OpenVDB file is damaged: a metadata "
                                         "name of 4026531840 bytes"),
              std::string::npos)
        << e.what();
  }
}

TEST(VdbGrid, AModelNodeReadsAGridByNameAndMeshesPrintable) {
  const std::string path = sampleFolder() + "/named.vdb";
  GridSet two = sampledSphere(0.05, 1.0);
  GridSet small = sampledSphere(0.05, 0.5);
  small.impl->grids[0]->setName("small");
  two.impl->grids.push_back(small.impl->grids[0]);
  writeVdb(two, path);
  registerVolumeSources();
  const NodePtr n =
      makeNode("vdb_grid", {{"path", textValue(path)}, {"grid", textValue("small")}}, {});
  const Program p = compile(n);
  EXPECT_NEAR(p.eval(0, 0, 0.4), 0.1, 0.01);
  EXPECT_LT(p.eval(0, 0, 0.7), 0);
  MeshingOptions m;
  m.bbox = structuralBounds(n);
  m.resolution = 0.03;
  const CheckReport r = checkMesh(polygonize(p, m));
  EXPECT_TRUE(r.printable()) << reportToText(r, "small");
  EXPECT_NEAR(r.volume, 4.0 / 3.0 * M_PI * 0.125, 0.03 * 4.0 / 3.0 * M_PI * 0.125);
  try {
    compile(makeNode("vdb_grid", {{"path", textValue(path)}, {"grid", textValue("big")}}, {}));
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("no grid named 'big'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace frep

namespace frep {
namespace {

// The active voxels of two grids: the same set, with bit-identical values.
template <class GridT>
bool sameActiveVoxels(const openvdb::GridBase& x, const openvdb::GridBase& y) {
  const auto& a = static_cast<const GridT&>(x);
  const auto& b = static_cast<const GridT&>(y);
  if (a.activeVoxelCount() != b.activeVoxelCount()) return false;
  auto acc = b.getConstAccessor();
  for (auto it = a.tree().cbeginValueOn(); it; ++it) {
    if (!acc.isValueOn(it.getCoord())) return false;
    const auto v = acc.getValue(it.getCoord());
    if (std::memcmp(&v, &*it, sizeof v) != 0) return false;
  }
  return true;
}

// A grid of one value type holding `value` over a box of voxels (all active).
template <class GridT>
typename GridT::Ptr blockGrid(const std::string& name, typename GridT::ValueType value,
                              double voxel, const openvdb::CoordBBox& box) {
  auto g = GridT::create(typename GridT::ValueType());
  g->setName(name);
  g->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
  g->denseFill(box, value, true);
  g->tree().voxelizeActiveTiles();
  return g;
}

FfdLattice stretchedAlongX(const Box3& rest, double factor) {
  FfdLattice lattice(rest, 1, 1, 1);
  for (int j = 0; j <= 1; ++j)
    for (int k = 0; k <= 1; ++k) {
      Vec3 p = lattice.point(1, j, k);
      p[0] = rest.lo[0] + factor * (rest.hi[0] - rest.lo[0]);
      lattice.setPoint(1, j, k, p);
    }
  return lattice;
}

TEST(GridFfd, TheUndeformedLatticeGivesEveryGridBackBitForBit) {
  initializeOpenVdb();
  openvdb::GridPtrVec grids;
  grids.push_back(sampledSphere(0.1).impl->grids[0]);
  grids.push_back(filledGrid<openvdb::DoubleGrid>("temperature", 1e-300, 3.14159265358979));
  grids.push_back(filledGrid<openvdb::Int32Grid>("label", 7, -123456));
  grids.push_back(filledGrid<openvdb::BoolGrid>("mask", false, true));
  grids.push_back(filledGrid<openvdb::Vec3SGrid>("velocity", openvdb::Vec3s(1, 2, 3),
                                                 openvdb::Vec3s(-0.5f, 0, 1e-7f)));
  const GridSet set = gridSetOf(grids);
  // A rest box holding part of each grid: inside it the map is the identity, outside it
  // nothing moves.
  const GridSet back = deformGrids(set, FfdLattice({{-1.5, -1.0, -1.2}, {1.3, 4.0, 1.0}}, 3, 2, 4));
  ASSERT_EQ(back.size(), set.size());
  for (std::size_t i = 0; i < set.size(); ++i) {
    const openvdb::GridBase& x = *set.impl->grids[i];
    const openvdb::GridBase& y = *back.impl->grids[i];
    EXPECT_EQ(set.info(i).name, back.info(i).name);
    EXPECT_EQ(set.info(i).gridClass, back.info(i).gridClass);
    bool same = false;
    if (x.isType<openvdb::FloatGrid>()) same = sameActiveVoxels<openvdb::FloatGrid>(x, y);
    if (x.isType<openvdb::DoubleGrid>()) same = sameActiveVoxels<openvdb::DoubleGrid>(x, y);
    if (x.isType<openvdb::Int32Grid>()) same = sameActiveVoxels<openvdb::Int32Grid>(x, y);
    if (x.isType<openvdb::BoolGrid>()) same = sameActiveVoxels<openvdb::BoolGrid>(x, y);
    if (x.isType<openvdb::Vec3SGrid>()) same = sameActiveVoxels<openvdb::Vec3SGrid>(x, y);
    EXPECT_TRUE(same) << set.info(i).name << " changed under the undeformed lattice";
  }
  // The level set's inside is still inside (flood-filled).
  const auto& ls = static_cast<const openvdb::FloatGrid&>(*back.impl->grids[0]);
  EXPECT_LT(ls.tree().getValue(openvdb::Coord(0, 0, 0)), 0.0f);
}

// The acceptance point: a level set stretched 2.5 times along x. Pulled back through the
// inverse, its mesh is printable; seed 002's forward splat leaves gaps, and its mesh is not.
TEST(GridFfd, AStretchedLevelSetHasNoHolesWhereForwardSplattingLeavesGaps) {
  const GridSet sphere = sampledSphere(0.08);
  const FfdLattice lattice = stretchedAlongX({{-1.3, -1.3, -1.3}, {1.3, 1.3, 1.3}}, 2.5);
  const GridSet pulled = deformGrids(sphere, lattice);
  const TriangleMesh good = levelSetToMesh(pulled, 0);
  const CheckReport report = checkMesh(good);
  EXPECT_TRUE(report.printable());
  // The stretched sphere: an ellipsoid with semi-axes 2.5, 1, 1 (centre moved by the stretch).
  double worst = 0;
  for (const Vec3f& p : good.positions) {
    const double x = (p[0] - (-1.3 + 2.5 * 1.3)) / 2.5;
    worst = std::max(worst, std::abs(norm3(x, p[1], p[2]) - 1.0));
  }
  EXPECT_LT(worst, 0.08);  // within a voxel of the ellipsoid (in the unstretched measure)

  GridFfdOptions splat;
  splat.method = GridFfdOptions::Method::ForwardSplat;
  const GridSet splatted = deformGrids(sphere, lattice, splat);
  // Gaps: voxels of the stretched narrow band that no source voxel landed on.
  const auto& a = static_cast<const openvdb::FloatGrid&>(*pulled.impl->grids[0]);
  const auto& b = static_cast<const openvdb::FloatGrid&>(*splatted.impl->grids[0]);
  auto bacc = b.getConstAccessor();
  std::size_t band = 0, gaps = 0;
  for (auto it = a.tree().cbeginValueOn(); it; ++it)
    if (std::abs(*it) < 0.08f) {
      ++band;
      gaps += !bacc.isValueOn(it.getCoord());
    }
  EXPECT_GT(gaps, band / 4) << gaps << " of " << band;
  EXPECT_FALSE(checkMesh(levelSetToMesh(splatted, 0)).printable());
}

TEST(GridFfd, VectorsTransformByTheJacobianAsTheirVectorTypeSays) {
  initializeOpenVdb();
  // A shear x' = x + 0.5 z over the rest box: dy/dx = [[1, 0, 0.5], [0, 1, 0], [0, 0, 1]].
  const Box3 rest{{-2, -2, -2}, {2, 2, 2}};
  FfdLattice lattice(rest, 1, 1, 1);
  for (int i = 0; i <= 1; ++i)
    for (int j = 0; j <= 1; ++j)
      for (int k = 0; k <= 1; ++k) {
        Vec3 p = lattice.point(i, j, k);
        p[0] += 0.5 * p[2];
        lattice.setPoint(i, j, k, p);
      }
  const openvdb::CoordBBox block(openvdb::Coord(-5), openvdb::Coord(5));
  openvdb::GridPtrVec grids;
  auto rel = blockGrid<openvdb::Vec3SGrid>("velocity", openvdb::Vec3s(0, 0, 1), 0.1, block);
  rel->setVectorType(openvdb::VEC_CONTRAVARIANT_RELATIVE);
  auto normal = blockGrid<openvdb::Vec3DGrid>("normal", openvdb::Vec3d(1, 0, 0), 0.1, block);
  normal->setVectorType(openvdb::VEC_COVARIANT);
  auto unit = blockGrid<openvdb::Vec3SGrid>("unit", openvdb::Vec3s(1, 0, 0), 0.1, block);
  unit->setVectorType(openvdb::VEC_COVARIANT_NORMALIZE);
  auto untagged = blockGrid<openvdb::Vec3SGrid>("untagged", openvdb::Vec3s(0, 0, 1), 0.1, block);
  grids = {rel, normal, unit, untagged};
  const GridSet out = deformGrids(gridSetOf(grids), lattice);
  auto at = [&](std::size_t g) {
    // a voxel well inside the moved block: (x, z) = (0.25, 0.2) came from (0.15, 0.2)
    const openvdb::Coord c(2, 0, 2);
    if (auto s = openvdb::gridPtrCast<openvdb::Vec3SGrid>(out.impl->grids[g])) {
      EXPECT_TRUE(s->tree().isValueOn(c));
      const auto v = s->tree().getValue(c);
      return Vec3{v[0], v[1], v[2]};
    }
    const auto d = openvdb::gridPtrCast<openvdb::Vec3DGrid>(out.impl->grids[g]);
    EXPECT_TRUE(d->tree().isValueOn(c));
    const auto v = d->tree().getValue(c);
    return Vec3{v[0], v[1], v[2]};
  };
  const Vec3 v = at(0), n = at(1), u = at(2), w = at(3);
  EXPECT_NEAR(v[0], 0.5, 1e-6);  // J (0, 0, 1) = (0.5, 0, 1)
  EXPECT_NEAR(v[2], 1.0, 1e-6);
  EXPECT_NEAR(n[0], 1.0, 1e-9);  // J^-T (1, 0, 0) = (1, 0, -0.5)
  EXPECT_NEAR(n[2], -0.5, 1e-9);
  EXPECT_NEAR(u[0], 1 / std::sqrt(1.25), 1e-6);  // the same, normalised
  EXPECT_NEAR(u[2], -0.5 / std::sqrt(1.25), 1e-6);
  EXPECT_NEAR(w[0], 0.5, 1e-6);  // untagged: a direction, like velocity
  GridFfdOptions keep;
  keep.keepVectors = true;
  const GridSet kept = deformGrids(gridSetOf(grids), lattice, keep);
  EXPECT_EQ(openvdb::gridPtrCast<openvdb::Vec3SGrid>(kept.impl->grids[0])
                ->tree()
                .getValue(openvdb::Coord(2, 0, 2)),
            openvdb::Vec3s(0, 0, 1));
}

TEST(GridFfd, AVdbWithThreeGridsOfDifferentTypesRoundTripsDeformed) {
  initializeOpenVdb();
  const openvdb::CoordBBox block(openvdb::Coord(-8, -4, -4), openvdb::Coord(8, 4, 4));
  openvdb::GridPtrVec grids;
  auto density = blockGrid<openvdb::FloatGrid>("density", 0.5f, 0.1, block);
  density->setGridClass(openvdb::GRID_FOG_VOLUME);
  auto acc = density->getAccessor();
  for (auto it = density->beginValueOn(); it; ++it)
    it.setValue(0.01f * float(it.getCoord().x() + 10));
  grids.push_back(density);
  grids.push_back(blockGrid<openvdb::Int32Grid>("label", 42, 0.1, block));
  grids.push_back(blockGrid<openvdb::Vec3SGrid>("velocity", openvdb::Vec3s(1, 0, 0), 0.1, block));
  const FfdLattice lattice =
      testing::twistedLattice(2, 2, 2, 0.8, 0.1, 3, Box3{{-1, -0.6, -0.6}, {1, 0.6, 0.6}});
  const GridSet out = deformGrids(gridSetOf(grids), lattice);
  const std::string path = sampleFolder() + "/deformed.vdb";
  writeVdb(out, path);
  const GridSet back = readVdb(path);
  ASSERT_EQ(back.size(), 3u);
  const FfdMap map(lattice);
  for (std::size_t i = 0; i < 3; ++i) {
    std::size_t j = 0;
    while (j < back.size() && back.info(j).name != out.info(i).name) ++j;
    ASSERT_LT(j, back.size());
    EXPECT_EQ(back.info(j).valueType, out.info(i).valueType);
    EXPECT_EQ(back.info(j).activeVoxels, out.info(i).activeVoxels);
    EXPECT_GT(out.info(i).activeVoxels, 1000u);
  }
  // Every deformed density voxel holds the source's value where the lattice came from.
  const auto& d = static_cast<const openvdb::FloatGrid&>(*out.impl->grids[0]);
  openvdb::tools::GridSampler<openvdb::FloatTree, openvdb::tools::BoxSampler> sampler(
      density->tree(), density->transform());
  std::size_t checked = 0;
  for (auto it = d.tree().cbeginValueOn(); it; ++it) {
    const openvdb::Vec3d p = d.transform().indexToWorld(it.getCoord());
    const auto s = map.inverse({p[0], p[1], p[2]});
    if (!s) continue;
    const Vec3 q = lattice.restPoint(*s);
    EXPECT_NEAR(*it, sampler.wsSample(openvdb::Vec3d(q[0], q[1], q[2])), 1e-5);
    ++checked;
  }
  EXPECT_GT(checked, 1000u);
  EXPECT_TRUE(sameActiveVoxels<openvdb::Int32Grid>(*out.impl->grids[1], *back.impl->grids[1]) ||
              sameActiveVoxels<openvdb::Int32Grid>(*out.impl->grids[1], *back.impl->grids[0]) ||
              sameActiveVoxels<openvdb::Int32Grid>(*out.impl->grids[1], *back.impl->grids[2]));
}

TEST(GridFfd, BadInputsAreRefusedWithTheReasonAndCancelStops) {
  initializeOpenVdb();
  const openvdb::CoordBBox block(openvdb::Coord(-4), openvdb::Coord(4));
  auto wide = blockGrid<openvdb::Int64Grid>("ids", 5, 0.1, block);
  try {
    deformGrids(gridSetOf({wide}), stretchedAlongX({{-1, -1, -1}, {1, 1, 1}}, 2));
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("grid 'ids' holds int64 values; allowed: float"),
              std::string::npos)
        << e.what();
  }
  auto f = blockGrid<openvdb::FloatGrid>(
      "density", 1.0f, 0.01, openvdb::CoordBBox(openvdb::Coord(-40), openvdb::Coord(40)));
  GridFfdOptions small;
  small.maxVoxels = 100000;
  try {
    deformGrids(gridSetOf({f}), stretchedAlongX({{-1, -1, -1}, {1, 1, 1}}, 30), small);
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("would need more than 100000 voxels"), std::string::npos)
        << e.what();
  }
  GridFfdOptions cancel;
  int calls = 0;
  cancel.progress = [&](double) { return ++calls < 1; };
  EXPECT_THROW(deformGrids(gridSetOf({f}), stretchedAlongX({{-1, -1, -1}, {1, 1, 1}}, 1.5), cancel),
               Cancelled);
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace frep

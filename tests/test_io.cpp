// Writers and readers: round trips, atomic writes (no partial file), clear errors.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "frep/errors.h"
#include "frep/tree.h"
#include "mesh/mesh_io.h"
#include "mesh/mesher.h"
#include "mesh/openmesh_bridge.h"

namespace fs = std::filesystem;

namespace frep {
namespace {

class MeshIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("frepcad-io-" + std::to_string(getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    MeshingOptions o;
    o.bbox = {{-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}};
    o.resolution = 0.2;
    mesh_ = polygonize(compile(makeNode("torus", {}, {})), o);
    ASSERT_GT(mesh_.triangleCount(), 100u);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::size_t filesInDir() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }

  fs::path dir_;
  TriangleMesh mesh_;
};

// Triangles as coordinate triples, independent of vertex indexing.
std::vector<std::array<float, 9>> corners(const TriangleMesh& m) {
  std::vector<std::array<float, 9>> out;
  for (const auto& t : m.triangles) {
    std::array<float, 9> c{};
    for (int i = 0; i < 3; ++i)
      for (int a = 0; a < 3; ++a) c[i * 3 + a] = m.positions[t[i]][a];
    out.push_back(c);
  }
  return out;
}

TEST_F(MeshIo, EveryFormatRoundTripsTheSameTriangles) {
  for (MeshFormat f : {MeshFormat::StlBinary, MeshFormat::StlAscii, MeshFormat::Obj, MeshFormat::Ply}) {
    const std::string p = path(std::string("m.") + (f == MeshFormat::Obj ? "obj" : f == MeshFormat::Ply ? "ply" : "stl"));
    writeMesh(mesh_, p, f);
    const TriangleMesh back = readMesh(p);
    EXPECT_EQ(corners(back), corners(mesh_)) << formatName(f);
    if (f == MeshFormat::Obj || f == MeshFormat::Ply) EXPECT_EQ(back.triangles, mesh_.triangles);
  }
  EXPECT_EQ(filesInDir(), 3u);  // m.stl (twice), m.obj, m.ply: no temporaries left
}

TEST_F(MeshIo, CancelledWriteLeavesNoFileAndKeepsTheOldOne) {
  const std::string p = path("part.stl");
  EXPECT_THROW(writeMesh(mesh_, p, MeshFormat::StlAscii, [](double) { return false; }), Cancelled);
  EXPECT_FALSE(fs::exists(p));
  EXPECT_EQ(filesInDir(), 0u);
  std::ofstream(p) << "old";
  EXPECT_THROW(writeMesh(mesh_, p, MeshFormat::StlBinary, [](double f) { return f < 0.5; }), Cancelled);
  std::ifstream in(p);
  std::string content;
  in >> content;
  EXPECT_EQ(content, "old");
  EXPECT_EQ(filesInDir(), 1u);
}

TEST_F(MeshIo, UnwritableFolderIsAClearError) {
  try {
    writeMesh(mesh_, path("missing/part.stl"), MeshFormat::StlBinary);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write in folder"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path("missing")));
}

TEST_F(MeshIo, BadFilesAreClearErrors) {
  EXPECT_THROW(readMesh(path("nothing.stl")), FileError);
  EXPECT_THROW(formatFromPath("part.step"), FileError);
  std::ofstream(path("junk.stl")) << "this is not an stl file at all, not even close to one....";
  try {
    readMesh(path("junk.stl"));
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("not an STL file"), std::string::npos);
  }
  std::ofstream(path("bad.obj")) << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
  EXPECT_THROW(readMesh(path("bad.obj")), FileError);
  EXPECT_THROW(parseFormat("3mf"), ModelError);
}

TEST_F(MeshIo, OpenMeshBridgeKeepsTheMesh) {
  const OMesh om = toOpenMesh(mesh_);
  EXPECT_EQ(om.n_faces(), mesh_.triangleCount());
  EXPECT_EQ(om.n_vertices(), mesh_.vertexCount());
  for (auto h : om.halfedges()) ASSERT_FALSE(om.is_boundary(h));  // closed
  const TriangleMesh back = fromOpenMesh(om);
  EXPECT_EQ(back.triangles, mesh_.triangles);
}

}  // namespace
}  // namespace frep

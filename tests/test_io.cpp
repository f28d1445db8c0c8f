// Writers and readers: round trips, atomic writes (no partial file), clear errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/errors.h"
#include "base/file_names.h"
#include "base/triangle_adjacency.h"
#include "frep/tree.h"
#include "io/mesh_io.h"
#include "mesh/mesher.h"
#include "mesh/openmesh_bridge.h"

namespace fs = std::filesystem;

namespace frep {
namespace {

class MeshIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("frepcad-io-" + std::to_string(getpid()) + "-" +
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
    return static_cast<std::size_t>(
        std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
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
  for (MeshFormat f : {MeshFormat::StlBinary, MeshFormat::StlAscii, MeshFormat::Obj,
                       MeshFormat::Ply, MeshFormat::FreecadBms}) {
    const std::string ext = f == MeshFormat::StlAscii ? "stl" : formatName(f);
    const std::string p = path("m." + ext);
    writeMesh(mesh_, p, f);
    const TriangleMesh back = readMesh(p);
    EXPECT_EQ(corners(back), corners(mesh_)) << formatName(f);
    if (f != MeshFormat::StlBinary && f != MeshFormat::StlAscii) {
      EXPECT_EQ(back.triangles, mesh_.triangles);
    }
  }
  EXPECT_EQ(filesInDir(), 4u);  // m.stl (twice), m.obj, m.ply, m.bms: no temporaries left
}

TEST_F(MeshIo, FreecadMeshLayoutAndNeighbours) {
  const std::string p = path("m.bms");
  writeMesh(mesh_, p, MeshFormat::FreecadBms);
  std::ifstream in(p, std::ios::binary);
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t nv = mesh_.vertexCount(), nf = mesh_.triangleCount();
  ASSERT_EQ(data.size(), 272 + 12 * nv + 24 * nf + 24);
  std::uint32_t word;
  std::memcpy(&word, data.data(), 4);
  EXPECT_EQ(word, 0xA0B0C0D0u);
  // Neighbour i of facet f lies across edge (i, i+1): it holds both ends of that edge, and
  // names f back. On a closed torus every edge has one.
  const char* facets = data.data() + 272 + 12 * nv;
  auto stored = [&](std::size_t f, int k) {
    std::uint32_t v;
    std::memcpy(&v, facets + 24 * f + 4 * k, 4);
    return v;
  };
  for (std::size_t f = 0; f < nf; ++f)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t g = stored(f, 3 + i);
      ASSERT_LT(g, nf);
      const auto& t = mesh_.triangles[g];
      for (std::uint32_t v : {mesh_.triangles[f][i], mesh_.triangles[f][(i + 1) % 3]})
        EXPECT_TRUE(t[0] == v || t[1] == v || t[2] == v);
      EXPECT_TRUE(stored(g, 3) == f || stored(g, 4) == f || stored(g, 5) == f);
    }
  // The box: min x, max x, min y, max y, min z, max z.
  float box[6];
  std::memcpy(box, data.data() + data.size() - 24, 24);
  for (int a = 0; a < 3; ++a) {
    float lo = mesh_.positions[0][a], hi = lo;
    for (const Vec3f& q : mesh_.positions) {
      lo = std::min(lo, q[a]);
      hi = std::max(hi, q[a]);
    }
    EXPECT_EQ(box[2 * a], lo);
    EXPECT_EQ(box[2 * a + 1], hi);
  }
}

TEST(TriangleAdjacency, BorderAndNonManifoldEdgesHaveNoNeighbour) {
  // Three triangles on edge (0, 1): non-manifold. Triangle 3 shares edge (1, 2) with 0 only.
  TriangleMesh m;
  m.positions.resize(6);
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {1, 0, 4}, {2, 1, 5}};
  const auto n = facetNeighbours(m);
  EXPECT_EQ(n[0][0], kNoNeighbour);  // (0, 1): three facets
  EXPECT_EQ(n[0][1], 3u);            // (1, 2)
  EXPECT_EQ(n[3][0], 0u);            // (2, 1)
  EXPECT_EQ(n[0][2], kNoNeighbour);  // (2, 0): border
  EXPECT_EQ(n[3][1], kNoNeighbour);  // (1, 5): border
}

TEST_F(MeshIo, FreecadMeshWithBadIndexIsAClearError) {
  const std::string p = path("bad.bms");
  writeMesh(mesh_, p, MeshFormat::FreecadBms);
  {
    std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(272 + 12 * mesh_.vertexCount());  // first facet's first point index
    const std::uint32_t big = 0x7FFFFFFF;
    f.write(reinterpret_cast<const char*>(&big), 4);
  }
  try {
    readMesh(p);
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("facet 0 has point index 2147483647 out of range"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(MeshIo, CancelledWriteLeavesNoFileAndKeepsTheOldOne) {
  const std::string p = path("part.stl");
  EXPECT_THROW(writeMesh(mesh_, p, MeshFormat::StlAscii, [](double) { return false; }), Cancelled);
  EXPECT_FALSE(fs::exists(p));
  EXPECT_EQ(filesInDir(), 0u);
  std::ofstream(p) << "old";
  EXPECT_THROW(writeMesh(mesh_, p, MeshFormat::StlBinary, [](double f) { return f < 0.5; }),
               Cancelled);
  std::ifstream in(p);
  std::string content;
  in >> content;
  EXPECT_EQ(content, "old");
  EXPECT_EQ(filesInDir(), 1u);
  // a 3MF cancelled after its vertices: the deflate workers stop, no temporary or spill left
  EXPECT_THROW(
      writeMesh(mesh_, path("part.3mf"), MeshFormat::ThreeMf, [](double f) { return f < 0.5; }),
      Cancelled);
  EXPECT_EQ(filesInDir(), 1u);
}

TEST_F(MeshIo, ReadingStopsWhenCancelled) {
  // Half a million triangles: more than one block of the file and of the triangles, so the
  // reader looks at the cancel after it has started, and reads everything when not asked.
  TriangleMesh big;
  for (std::uint32_t t = 0; t < 500000; ++t) {
    const float x = static_cast<float>(t);
    big.positions.push_back({x, 0, 0});
    big.positions.push_back({x, 1, 0});
    big.positions.push_back({x, 0, 1});
    big.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  for (MeshFormat f : {MeshFormat::StlBinary, MeshFormat::Obj}) {
    const std::string p = path(f == MeshFormat::Obj ? "big.obj" : "big.stl");
    writeMesh(big, p, f);
    int calls = 0;
    EXPECT_THROW(readMesh(p, ProgressCallback([&calls](double) { return ++calls < 2; })),
                 Cancelled);
    EXPECT_EQ(calls, 2);
    EXPECT_EQ(readMesh(p, ProgressCallback([](double) { return true; })).triangles.size(),
              500000u);
  }
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
  EXPECT_THROW(parseFormat("amf"), ModelError);
  EXPECT_EQ(parseFormat("3mf"), MeshFormat::ThreeMf);
}

// The torus as OFF text, written here (frepcad reads OFF, it does not write it).
std::string offText(const TriangleMesh& m, const std::string& header) {
  std::ostringstream os;
  os.precision(9);
  os << header << "\n# a comment line\n" << m.vertexCount() << " " << m.triangleCount() << " 0\n";
  for (const Vec3f& p : m.positions) os << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (const Triangle& t : m.triangles) os << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return os.str();
}

TEST_F(MeshIo, OffFilesReadTheSameTriangles) {
  std::ofstream(path("torus.off")) << offText(mesh_, "OFF");
  EXPECT_EQ(corners(readMesh(path("torus.off"))), corners(mesh_));
  // counts on the keyword's line, a quad (fan-triangulated), per-vertex colours, upper-case
  // extension
  std::ofstream(path("quad.OFF")) << "COFF 4 1 0\n0 0 0 255 0 0 255\n1 0 0 255 0 0 255\n"
                                     "1 1 0 255 0 0 255\n0 1 0 255 0 0 255\n4 0 1 2 3\n";
  const TriangleMesh quad = readMesh(path("quad.OFF"));
  EXPECT_EQ(quad.vertexCount(), 4u);
  EXPECT_EQ(quad.triangleCount(), 2u);
}

// Every reader takes a number only when the whole word is one, and refuses a file whose
// header promises more than it holds, before reserving for it.
TEST_F(MeshIo, ReadersRefuseWhatIsNotWhatItClaims) {
  const std::string tetraV = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
  const std::string plyHead =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::vector<std::array<std::string, 3>> cases = {
      {"fraction.obj", tetraV + "f 1.9 2.9 3.9\n", "'1.9' is not a whole number"},
      {"suffix.obj", tetraV + "f 1abc 2 3\n", "'1abc' is not a whole number"},
      {"zero.obj", tetraV + "f 0 1 2\n", "face index 0; OBJ counts vertices from 1"},
      {"word.obj", "v 0 0 one\n", "'one' is not a finite number"},
      {"nan.obj", "v 0 nan 0\n", "'nan' is not a finite number"},
      {"points.obj", tetraV, "no faces (4 vertices)"},
      {"int128.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty int128 x\nend_header\n1\n",
       "PLY property type 'int128' is not one of"},
      {"fraction.ply", plyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n", "'2.5' is not a whole number"},
      {"negative.ply", "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n",
       "element count -3 is negative"},
      {"lying.off", "OFF\n4 4000000 0\n0 0 0\n1 0 0\n", "more than"},
      {"short.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n", "OFF ends after 0 of 1 faces"},
      {"listed.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", "says 4 vertices but lists 3"},
      {"binary.off", "OFF BINARY\n", "binary OFF is not supported"},
      {"noff.off", "STL 3 1 0\n", "not an OFF file"},
  };
  for (const auto& [name, text, expected] : cases) {
    std::ofstream(path(name)) << text;
    try {
      readMesh(path(name));
      ADD_FAILURE() << name << " was read";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
          << name << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

// The type comes from the file name's extension, not from a dot in a folder's name.
TEST_F(MeshIo, TheExtensionIsTheFileNames) {
  EXPECT_EQ(fileExtension("a.b/c.STL"), "stl");
  EXPECT_EQ(fileExtension("scans.atos/out7/o"), "");
  EXPECT_EQ(fileExtension("dir/.hidden"), "");
  EXPECT_TRUE(isVdbPath("X.VDB"));
  EXPECT_FALSE(isVdbPath("x.vdb/part.stl"));
  fs::create_directories(dir_ / "scans.atos");
  try {
    readMesh(path("scans.atos/o"));
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("the file name has no extension"), std::string::npos)
        << e.what();
  }
  writeMesh(mesh_, path("upper.PLY"), formatFromPath(path("upper.PLY")));
  EXPECT_EQ(corners(readMesh(path("upper.PLY"))), corners(mesh_));
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

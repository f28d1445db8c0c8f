// Manufacturing output: 3MF files through lib3mf, the printability report, and the
// distance between meshes (repair: test_repair.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "check/mesh_deviation.h"
#include "check/printability.h"
#include "frep/program.h"
#include "frep/tree.h"
#include "io/mesh_3mf.h"
#include "io/mesh_io.h"
#include "io/three_mf_stream.h"
#include "mesh/mesher.h"
#include "repair_samples.h"

namespace frep {
namespace {

namespace fs = std::filesystem;

std::string reasons(const CheckReport& r) {
  std::string s;
  for (const std::string& x : r.reasons) s += x + "; ";
  return s;
}

std::string tempPath(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "frep_manufacturing";
  fs::create_directories(dir);
  return (dir / name).string();
}

// ---- 3MF ---------------------------------------------------------------------------------

TEST(ThreeMf, WrittenObjectsReadBackWithTheSameGeometryUnitAndMetadata) {
  const TriangleMesh a = sphereMesh(1.0, {0, 0, 0});
  TriangleMesh b = gridBox({3, 0, 0}, {4.123456789, 1.5, 2.25}, 3);
  // Coordinates of every size, to the float's last bit.
  for (auto& p : b.positions) p[2] += 1234.56789f;
  const std::string path = tempPath("two.3mf");
  ThreeMfOptions o;
  o.unit = LengthUnit::Centimeter;
  o.metadata = {{"Title", "two objects"}, {"Designer", "FRepCAD tests"}};
  write3mf({{"sphere", a}, {"block", b}}, path, o);
  const ThreeMfContents c = read3mf(path);
  ASSERT_EQ(c.objects.size(), 2u);
  EXPECT_EQ(c.objects[0].name, "sphere");
  EXPECT_EQ(c.objects[1].name, "block");
  EXPECT_EQ(c.unit, LengthUnit::Centimeter);
  bool title = false;
  for (const auto& [k, v] : c.metadata) title = title || (k == "Title" && v == "two objects");
  EXPECT_TRUE(title);
  // The file holds the written meshes bit for bit (lib3mf's own writer rounded to six
  // decimals, so the 1234.56789 offsets moved).
  const TriangleMesh* written[] = {&a, &b};
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(c.objects[k].mesh.triangles, written[k]->triangles);
    EXPECT_EQ(c.objects[k].mesh.positions, written[k]->positions);
  }
  // readMesh merges the build: both objects, still printable.
  const CheckReport r = checkMesh(readMesh(path));
  EXPECT_TRUE(r.printable()) << reasons(r);
  EXPECT_EQ(r.components, 2u);
}

// The streamed package (io/three_mf_stream.h), as a brick merge writes it: vertices and
// triangles interleaved (the triangles spilled until the vertices close), and a whole mesh;
// with and without the zip64 headers. lib3mf reads it back bit for bit.
TEST(ThreeMf, AStreamedPackageHoldsEveryCoordinateExactly) {
  const TriangleMesh a = sphereMesh(1.0, {0, 0, 0});
  TriangleMesh b = gridBox({3, 0, 0}, {4.123456789, 1.5, 2.25}, 3);
  for (auto& p : b.positions) p[2] += 1234.56789f;
  b.positions[0][0] = 1e-7f;  // (an exponent in the text)
  b.positions[1][1] = -0.0f;
  for (const bool zip64 : {false, true}) {
    const std::string path = tempPath(zip64 ? "stream64.3mf" : "stream.3mf");
    ThreeMfOptions o;
    o.unit = LengthUnit::Inch;
    // (lib3mf 1.8 reads a metadata value's text without decoding entities: the escaping is
    // tested through the object's name)
    o.metadata = {{"Title", "streamed, exactly"}};
    ThreeMfStreamWriter w(path, o, zip64 ? std::uint64_t(8) << 30 : 1000);
    w.beginObject("sphere & <\"co\">");
    // each triangle as soon as its last corner is out, as the merge gives them
    std::vector<std::size_t> order(a.triangles.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
      const auto& tx = a.triangles[x];
      const auto& ty = a.triangles[y];
      return std::max({tx[0], tx[1], tx[2]}) < std::max({ty[0], ty[1], ty[2]});
    });
    std::size_t next = 0;
    for (std::uint32_t v = 0; v < a.positions.size(); ++v) {
      w.vertex(a.positions[v]);
      for (; next < order.size(); ++next) {
        const auto& t = a.triangles[order[next]];
        if (std::max({t[0], t[1], t[2]}) > v) break;
        w.triangle(t);
      }
    }
    w.endObject();
    w.addObject("block", b);
    EXPECT_EQ(w.triangles(), a.triangles.size() + b.triangles.size());
    w.finish()->commit();
    const ThreeMfContents c = read3mf(path);
    ASSERT_EQ(c.objects.size(), 2u);
    EXPECT_EQ(c.objects[0].name, "sphere & <\"co\">");
    EXPECT_EQ(c.objects[1].name, "block");
    EXPECT_EQ(c.unit, LengthUnit::Inch);
    ASSERT_EQ(c.metadata.size(), 1u);
    EXPECT_EQ(c.metadata[0].first, "Title");
    EXPECT_EQ(c.metadata[0].second, "streamed, exactly");
    std::vector<Triangle> sorted;
    for (std::size_t i : order) sorted.push_back(a.triangles[i]);
    EXPECT_EQ(c.objects[0].mesh.triangles, sorted);
    EXPECT_EQ(c.objects[0].mesh.positions, a.positions);  // bit for bit
    EXPECT_EQ(c.objects[1].mesh.triangles, b.triangles);
    EXPECT_EQ(c.objects[1].mesh.positions, b.positions);
    EXPECT_GT(zipUnpackedBytes(path), 1000u);
    EXPECT_TRUE(checkMesh(c.objects[0].mesh).printable());
  }
}

TEST(ThreeMf, AStreamedObjectThatBreaksARuleIsRefusedByNameAndNothingIsLeft) {
  const std::string folder = tempPath("stream_refusals");
  fs::create_directories(folder);
  const std::string path = folder + "/refused.3mf";
  auto refuses = [&](const std::function<void(ThreeMfStreamWriter&)>& make, const char* words) {
    try {
      ThreeMfStreamWriter w(path, {}, 1000);
      make(w);
      w.finish()->commit();
      ADD_FAILURE() << "written: " << words;
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find("'bad part'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_empty(folder));  // neither the target, the temporary nor the spill
  };
  refuses(
      [](ThreeMfStreamWriter& w) {
        w.beginObject("bad part");
        w.vertex({0, 0, 0});
        w.triangle({0, 1, 2});  // (spilled: judged when the vertices close)
        w.vertex({1, 0, 0});
        w.vertex({0, 1, 0});
        w.triangle({0, 2, 3});
        w.endObject();
      },
      "refers to vertex 3 of 3");
  refuses(
      [](ThreeMfStreamWriter& w) {
        w.beginObject("bad part");
        w.vertex({0, 0, 0});
        w.vertex({0, std::nanf(""), 0});
      },
      "non-finite");
  refuses(
      [](ThreeMfStreamWriter& w) {
        TriangleMesh m;
        m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        m.triangles = {{0, 1, 1}};
        w.addObject("bad part", m);
      },
      "twice");
  refuses([](ThreeMfStreamWriter& w) { w.addObject("bad part", TriangleMesh{}); }, "no triangles");
}

TEST(ThreeMf, AnObjectThatBreaksTheCoreRulesIsRefusedByNameAndNothingIsWritten) {
  TriangleMesh open = gridBox({0, 0, 0}, {1, 1, 1}, 2);
  open.triangles.pop_back();
  const std::string path = tempPath("refused.3mf");
  fs::remove(path);
  try {
    write3mf({{"good", sphereMesh()}, {"leaky part", open}}, path);
    FAIL() << "an open object was written";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("leaky part"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("manifold"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
  for (const auto& entry : fs::directory_iterator(fs::path(path).parent_path()))
    EXPECT_EQ(entry.path().string().find("refused.3mf."), std::string::npos) << entry.path();
}

// lib3mf's own rule is about edges only: an inside-out solid passes it (as FreeCAD's check
// passes it), and the CGAL check read from the 3MF catches it.
TEST(ThreeMf, AnInsideOutMeshIsCaughtByTheCheck) {
  TriangleMesh m = sphereMesh();
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  const std::string path = tempPath("inside_out.3mf");
  write3mf({{"inside out", m}}, path);
  const CheckReport r = checkMesh(readMesh(path));
  EXPECT_FALSE(r.printable());
  EXPECT_TRUE(r.closed);
  EXPECT_FALSE(r.outward);
  EXPECT_LT(r.volume, 0);
}

TEST(ThreeMf, APackageThatUnpacksTooLargeIsRefusedBeforeReading) {
  const std::string path = tempPath("bomb.3mf");
  write3mf({{"sphere", sphereMesh()}}, path);
  EXPECT_LT(zipUnpackedBytes(path), 10u << 20);
  // Declare every entry 2 GiB unpacked in the central directory, as a zip bomb would.
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  int patched = 0;
  for (std::size_t i = 0; i + 46 <= bytes.size(); ++i)
    if (bytes.compare(i, 4, "PK\x01\x02", 4) == 0) {
      const std::uint32_t huge = 0x80000000u;
      f.seekp(static_cast<std::streamoff>(i + 24));
      f.write(reinterpret_cast<const char*>(&huge), 4);
      ++patched;
    }
  f.close();
  ASSERT_GE(patched, 3);
  EXPECT_GT(zipUnpackedBytes(path), kMax3mfUnpackedBytes);
  try {
    read3mf(path);
    FAIL() << "the bomb was read";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("refused before reading"), std::string::npos) << e.what();
  }
}

TEST(ThreeMf, GarbageIsAFileErrorNamingTheFile) {
  const std::string path = tempPath("garbage.3mf");
  std::ofstream(path) << "this is not a zip archive";
  try {
    read3mf(path);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("garbage.3mf"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseLengthUnit("furlong"), ModelError);
}

// ---- printability ------------------------------------------------------------------------

// A 10 mm hollow cube whose walls are 0.2 mm thick: the thinnest wall is found within 10 %.
TEST(Printability, TheWallOfAHollowCubeIsMeasuredWithinTenPercent) {
  const TriangleMesh m = merged(gridBox({0, 0, 0}, {10, 10, 10}, 8),
                                gridBox({0.2, 0.2, 0.2}, {9.8, 9.8, 9.8}, 8, true));
  const CheckReport c = checkMesh(m);
  ASSERT_TRUE(c.printable()) << reasons(c);
  PrintabilityOptions o;
  o.minWall = 0.5;
  o.density = 1.24;
  const PrintabilityReport p = measurePrintability(m, o);
  EXPECT_NEAR(p.minWall, 0.2, 0.02);
  EXPECT_EQ(p.thinTriangles, m.triangles.size());  // every wall is 0.2
  // The cavity's ceiling faces down and needs support; the outer bottom lies on the plate.
  EXPECT_NEAR(p.overhangArea, 9.6 * 9.6, 1e-3);
  const double volume = 1000 - 9.6 * 9.6 * 9.6;
  EXPECT_NEAR(p.volume, volume, 1e-3);
  EXPECT_NEAR(p.mass, volume * 1.24 / 1000, 1e-5);
  EXPECT_NEAR(p.height, 10, 1e-6);

  // A solid cube: its walls are 10 thick, nothing is thin, nothing overhangs.
  const PrintabilityReport solid = measurePrintability(gridBox({0, 0, 0}, {10, 10, 10}, 8), o);
  EXPECT_NEAR(solid.minWall, 10, 1.0);
  EXPECT_EQ(solid.thinTriangles, 0u);
  EXPECT_EQ(solid.overhangArea, 0.0);
  // Built along x instead, the face at x = 0 lies on the plate, and the cavity's face at
  // x = 9.8 (facing -x) is the ceiling.
  o.up = {1, 0, 0};
  EXPECT_NEAR(measurePrintability(m, o).overhangArea, 9.6 * 9.6, 1e-3);
}

TEST(Printability, CavitiesAreListedLargestFirstEachWithAPointInTheMiddleOfItsFloor) {
  // A 20 x 10 x 10 block with two hollows: 8 x 8 x 8 and 4 x 4 x 4.
  const TriangleMesh small = gridBox({11, 1, 1}, {15, 5, 5}, 4, true);
  const TriangleMesh m = merged(merged(gridBox({0, 0, 0}, {20, 10, 10}, 10),
                                       gridBox({1, 1, 1}, {9, 9, 9}, 8, true)),
                                small);
  ASSERT_TRUE(checkMesh(m).printable()) << reasons(checkMesh(m));
  PrintabilityOptions o;
  PrintabilityReport p = measurePrintability(m, o);
  ASSERT_EQ(p.cavities, 2);
  ASSERT_EQ(p.cavityList.size(), 2u);
  EXPECT_NEAR(p.cavityList[0].volume, 512, 1e-3);
  EXPECT_NEAR(p.cavityList[1].volume, 64, 1e-3);
  EXPECT_NEAR(p.cavityVolume, 576, 1e-3);
  // Each drains from the middle of its floor, not from the floor's edge beside a wall.
  EXPECT_NEAR(p.cavityList[0].drainAt[2], 1, 1e-6);
  EXPECT_NEAR(p.cavityList[0].drainAt[0], 5, 1.01);
  EXPECT_NEAR(p.cavityList[0].drainAt[1], 5, 1.01);
  EXPECT_NEAR(p.cavityList[1].drainAt[0], 13, 1.01);
  EXPECT_NEAR(p.cavityList[1].drainAt[2], 1, 1e-6);
  // Every triangle of a hollow's wall names its cavity; the outside names none.
  ASSERT_EQ(p.cavityOf.size(), m.triangles.size());
  const std::size_t outer = gridBox({0, 0, 0}, {20, 10, 10}, 10).triangles.size();
  const std::size_t inner = m.triangles.size() - outer - small.triangles.size();
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    EXPECT_EQ(p.cavityOf[i], i < outer ? -1 : i < outer + inner ? 0 : 1) << i;
  // Built along -x, the large hollow drains through its face at x = 9.
  o.up = {-1, 0, 0};
  p = measurePrintability(m, o);
  EXPECT_NEAR(p.cavityList[0].drainAt[0], 9, 1e-6);
  EXPECT_NEAR(p.cavityList[0].drainAt[1], 5, 1.01);
  // A solid has none.
  p = measurePrintability(gridBox({0, 0, 0}, {1, 1, 1}, 2), o);
  EXPECT_EQ(p.cavities, 0);
  EXPECT_TRUE(p.cavityList.empty());
}

TEST(Printability, BadOptionsAreRefused) {
  PrintabilityOptions o;
  o.up = {0, 0, 0};
  EXPECT_THROW(measurePrintability(sphereMesh(), o), ModelError);
  EXPECT_THROW(materialDensity("cheese"), ModelError);
  EXPECT_DOUBLE_EQ(materialDensity("pla"), 1.24);
}

TEST(Deviation, AMeshMovedByASmallDistanceIsThatFarAway) {
  const TriangleMesh a = gridBox({0, 0, 0}, {1, 1, 1}, 4);
  TriangleMesh b = a;
  for (auto& p : b.positions) p[2] += 0.01f;
  const DeviationReport d = meshDeviation(a, b);
  EXPECT_NEAR(d.hausdorff(), 0.01, 1e-4);
  // Most of the side faces' points lie on the moved sides too.
  EXPECT_GT(d.meanAToB, 0.0);
  EXPECT_LT(d.meanAToB, 0.006);
  EXPECT_EQ(meshDeviation(a, a).hausdorff(), 0.0);
}

}  // namespace
}  // namespace frep

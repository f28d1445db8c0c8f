// The Voronoi foam (volume/voronoi_foam.h, frep/periodic_segments.h): its edges are the
// Voronoi diagram's (points on them equidistant from their three nearest seeds, every vertex
// meeting four edges), the field is the distance to the nearest edge of the periodic network
// at 10,000 points (brute force over every copy), and the foam meshes printable.
#include <CGAL/Random.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "frep/field_sources.h"
#include "frep/periodic_segments.h"
#include "frep/tree.h"
#include "io/mesh_3mf.h"
#include "mesh/mesher.h"
#include "pipeline/beam_export.h"
#include "test_nodes.h"
#include "volume/field_sources.h"
#include "volume/voronoi_foam.h"

namespace frep {
namespace {

NodePtr foam(Vec3 cell, double radius, double nodeRadius = 0.0, int seed = 3, int tile = 4,
             Vec3 origin = {0, 0, 0}, double jitter = 1.0, std::vector<NodePtr> inputs = {}) {
  registerVolumeSources();
  return makeNode("voronoi_foam",
                  {{"cell", vec3Value(cell)},
                   {"radius", realValue(radius)},
                   {"node_radius", realValue(nodeRadius)},
                   {"seed", realValue(seed)},
                   {"jitter", realValue(jitter)},
                   {"tile", realValue(tile)},
                   {"origin", vec3Value(origin)}},
                  std::move(inputs));
}

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 e = vsub(b, a), d = vsub(p, a);
  const double l2 = vdot(e, e);
  const double t = l2 > 0 ? std::clamp(vdot(d, e) / l2, 0.0, 1.0) : 0.0;
  return vlength(vsub(d, vscale(e, t)));
}

Vec3 shifted(const Vec3& p, const Vec3& period, int i, int j, int k) {
  return {p[0] + i * period[0], p[1] + j * period[1], p[2] + k * period[2]};
}

// The distances from p (near the tile) to the four nearest seeds of the periodic foam (the
// tile's and their copies in the tiles round it), in order.
std::vector<double> seedDistances(const VoronoiFoamNetwork& net, const Vec3& p) {
  std::vector<double> d;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        for (const Vec3& s : net.seeds)
          d.push_back(vlength(vsub(p, shifted(s, net.period, i, j, k))));
  std::partial_sort(d.begin(), d.begin() + 4, d.end());
  d.resize(4);
  return d;
}

TEST(VoronoiFoam, ItsEdgesAreTheVoronoiDiagramsEdges) {
  VoronoiFoamSettings s;
  s.cell = {1.0, 1.2, 0.8};
  s.origin = {0.3, -0.2, 0.1};
  s.seed = 42;
  s.tile = 4;
  const VoronoiFoamNetwork net = voronoiFoamNetwork(s);
  // a period of at least 4 of the longest side (1.2) along each axis: 5 x 4 x 6 cells
  ASSERT_EQ(net.cells, (std::array<int, 3>{5, 4, 6}));
  ASSERT_EQ(net.seeds.size(), 120u);
  // every seed in its own cell of the grid
  for (std::size_t n = 0; n < net.seeds.size(); ++n) {
    const int index[3] = {int(n % 5), int(n / 5 % 4), int(n / 20)};
    for (int a = 0; a < 3; ++a) {
      const double u = (net.seeds[n][a] - s.origin[a]) / s.cell[a] - index[a];
      EXPECT_TRUE(u >= 0.0 && u < 1.0) << n;
    }
  }
  const double scale = 1e-9 * 1.2;
  // points along each edge: their three nearest seeds equidistant, the fourth farther
  for (const StrutPiece& e : net.edges)
    for (double t : {0.25, 0.5, 0.75}) {
      const Vec3 p = vadd(e.a, vscale(vsub(e.b, e.a), t));
      const std::vector<double> d = seedDistances(net, p);
      EXPECT_NEAR(d[0], d[2], scale) << "not on a Voronoi edge";
      if (vlength(vsub(e.b, e.a)) > 1e-6) {
        EXPECT_GT(d[3] - d[0], scale);
      }
    }
  // each vertex four seeds equidistant
  for (const Vec3& v : net.nodes) {
    const std::vector<double> d = seedDistances(net, v);
    EXPECT_NEAR(d[0], d[3], scale) << "not a Voronoi vertex";
  }
  // complete: in general position every vertex meets four edges, so the periodic diagram has
  // twice as many edges as vertices, and each vertex is an end of four edges (copies counted)
  EXPECT_EQ(net.edges.size(), 2 * net.nodes.size());
  auto periodicGap = [&](const Vec3& u, const Vec3& w) {  // |u - w| to w's nearest copy
    Vec3 d = vsub(u, w);
    for (int a = 0; a < 3; ++a) d[a] -= net.period[a] * std::round(d[a] / net.period[a]);
    return vlength(d);
  };
  for (const Vec3& v : net.nodes) {
    int ends = 0;
    for (const StrutPiece& e : net.edges)
      ends += (periodicGap(e.a, v) < scale) + (periodicGap(e.b, v) < scale);
    EXPECT_EQ(ends, 4);
  }
  // the same settings, the same foam to the last bit, built again (the triangulation stores
  // its cells in another order) and whatever CGAL's random numbers (seeded from the clock by
  // default); another seed, another
  for (unsigned cgalSeed : {0u, 1u, 977u}) {
    if (cgalSeed) CGAL::get_default_random() = CGAL::Random(cgalSeed);
    const VoronoiFoamNetwork again = voronoiFoamNetwork(s);
    ASSERT_EQ(again.edges.size(), net.edges.size());
    ASSERT_EQ(again.nodes.size(), net.nodes.size());
    for (std::size_t i = 0; i < net.edges.size(); ++i) {
      EXPECT_EQ(again.edges[i].a, net.edges[i].a);
      EXPECT_EQ(again.edges[i].b, net.edges[i].b);
    }
    EXPECT_EQ(again.nodes, net.nodes);
  }
  s.seed = 43;
  EXPECT_NE(voronoiFoamNetwork(s).seeds.front(), net.seeds.front());
}

// The figure: the field within 1e-9 of radius - the distance to the nearest edge (and
// node) of every copy of the tile, at 10,000 random points inside and beyond the tile.
TEST(VoronoiFoam, TheDistanceToTheNearestEdgeAtTenThousandPoints) {
  for (int variant = 0; variant < 2; ++variant) {
    VoronoiFoamSettings s;
    s.cell = variant ? Vec3{0.9, 0.6, 1.1} : Vec3{1, 1, 1};
    s.origin = variant ? Vec3{0.17, -0.4, 2.3} : Vec3{0, 0, 0};
    s.seed = 5 + variant;
    s.jitter = variant ? 0.6 : 1.0;
    s.tile = 4;
    const double radius = 0.07, nodeRadius = variant ? 0.12 : 0.0;
    const Program p =
        compile(foam(s.cell, radius, nodeRadius, int(s.seed), s.tile, s.origin, s.jitter));
    const VoronoiFoamNetwork net = voronoiFoamNetwork(s);
    double longest = 0;
    for (const StrutPiece& e : net.edges) longest = std::max(longest, vlength(vsub(e.b, e.a)));
    std::mt19937 rng(17 + variant);
    double worst = 0.0;
    for (int n = 0; n < 5000; ++n) {
      Vec3 q;
      for (int a = 0; a < 3; ++a)
        q[a] = s.origin[a] + std::uniform_real_distribution<double>(-0.5, 1.5)(rng) * net.period[a];
      // every copy of the tile, nearest tiles first, until a tile (grown by half the longest
      // edge: every edge's middle is in its tile) is farther than the nearest edge and node
      std::vector<std::pair<double, std::array<int, 3>>> tiles;
      for (int i = -2; i <= 2; ++i)
        for (int j = -2; j <= 2; ++j)
          for (int k = -2; k <= 2; ++k) {
            double d2 = 0;
            const int shift[3] = {i, j, k};
            for (int a = 0; a < 3; ++a) {
              const double lo = s.origin[a] + shift[a] * net.period[a] - 0.5 * longest;
              const double hi = lo + net.period[a] + longest;
              const double out = std::max({lo - q[a], q[a] - hi, 0.0});
              d2 += out * out;
            }
            tiles.push_back({std::sqrt(d2), {i, j, k}});
          }
      std::sort(tiles.begin(), tiles.end());
      double edge = HUGE_VAL, node = HUGE_VAL;
      for (const auto& [away, t] : tiles) {
        if (away > edge && (nodeRadius == 0 || away > node)) break;
        for (const StrutPiece& e : net.edges)
          edge = std::min(edge, distanceToSegment(q, shifted(e.a, net.period, t[0], t[1], t[2]),
                                                  shifted(e.b, net.period, t[0], t[1], t[2])));
        if (nodeRadius > 0)
          for (const Vec3& v : net.nodes)
            node = std::min(node, vlength(vsub(q, shifted(v, net.period, t[0], t[1], t[2]))));
      }
      double exact = radius - edge;
      if (nodeRadius > 0) exact = std::max(exact, nodeRadius - node);
      worst = std::max(worst, std::abs(p.eval(q[0], q[1], q[2]) - exact));
    }
    EXPECT_LT(worst, 1e-9) << "variant " << variant;
  }
}

// Smooth joints: the field is radius - the smooth minimum of the distances to every edge
// (brute force over every copy of the tile), exact away from the joints.
TEST(VoronoiFoam, SmoothJointsAreTheSmoothMinimumOfEveryEdge) {
  VoronoiFoamSettings s;
  s.seed = 9;
  s.tile = 4;
  const double radius = 0.05, blend = 0.1;
  registerVolumeSources();
  NodePtr node = foam(s.cell, radius, 0.0, int(s.seed), s.tile);
  auto params = node->params;
  params["blend"] = realValue(blend);
  const Program p = compile(makeNode("voronoi_foam", params, {}));
  const VoronoiFoamNetwork net = voronoiFoamNetwork(s);
  std::mt19937 rng(23);
  double worst = 0.0;
  int exactPoints = 0, blendedPoints = 0;
  for (int n = 0; n < 1000; ++n) {
    Vec3 q;
    for (int a = 0; a < 3; ++a)
      q[a] = std::uniform_real_distribution<double>(0.0, 1.0)(rng) * net.period[a];
    std::vector<double> d;  // (edges two periods away are farther than a period less one edge)
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        for (int k = -1; k <= 1; ++k)
          for (const StrutPiece& e : net.edges)
            d.push_back(distanceToSegment(q, shifted(e.a, net.period, i, j, k),
                                          shifted(e.b, net.period, i, j, k)));
    std::partial_sort(d.begin(), d.begin() + 2, d.end());
    const double m = d[0];
    double sum = 0.0;
    for (double di : d) sum += std::pow(std::max(0.0, 1.0 - (di - m) / blend), 2);
    const double value = p.eval(q[0], q[1], q[2]);
    worst = std::max(worst, std::abs(value - (radius - (m - 0.5 * blend + 0.5 * blend / sum))));
    if (d[1] - m >= blend) {
      EXPECT_NEAR(value, radius - m, 1e-9);
      ++exactPoints;
    } else {
      ++blendedPoints;
    }
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(exactPoints, 100);
  EXPECT_GT(blendedPoints, 100);
}

// Cut to a block, the foam meshes printable at three resolutions with the volume settling.
TEST(VoronoiFoam, MeshesPrintableAtThreeResolutions) {
  const NodePtr part =
      makeNode("intersection", {},
               {foam({1, 1, 1}, 0.08, 0.1), testing::box({-1.4, -1.4, -1.4}, {2.8, 2.8, 2.8})});
  const Program p = compile(part);
  double volumes[3];
  int r = 0;
  for (double h : {0.06, 0.04, 0.03}) {
    MeshingOptions o;
    o.bbox = {{-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}};
    o.resolution = h;
    const CheckReport report = checkMesh(polygonize(p, o));
    EXPECT_TRUE(report.printable()) << "at " << h;
    volumes[r++] = report.volume;
  }
  EXPECT_NEAR(volumes[1], volumes[2], 0.03 * volumes[2]);
  EXPECT_GT(volumes[2], 0.2);
}

// A field input grades the radius; the field's memory stays the same for any extent (it
// holds one tile) and under a megabyte for the default tile.
TEST(VoronoiFoam, AFieldInputGradesTheRadiusAndTheMemoryIsOneTiles) {
  const NodePtr radius = makeNode(
      "formula", {{"formula", textValue("0.05 + 0.02 * x")}, {"parameters", textValue("")}}, {});
  const Program graded = compile(foam({1, 1, 1}, 0.3, 0.0, 3, 4, {0, 0, 0}, 1.0, {radius}));
  const Program plain = compile(foam({1, 1, 1}, 0.3));
  for (double x : {-2.0, 0.3, 1.7})
    EXPECT_NEAR(graded.eval(x, 0.2, 0.1), plain.eval(x, 0.2, 0.1) - 0.3 + 0.05 + 0.02 * x, 1e-12);
  VoronoiFoamSettings s;  // the node's defaults
  const auto field = std::dynamic_pointer_cast<const PeriodicSegmentsField>(
      loadFieldSource(*foam(s.cell, 0.1, 0.0, int(s.seed), s.tile)));
  ASSERT_TRUE(field);
  EXPECT_LT(field->memoryBytes(), 1u << 20);
}

// An infill of foam: inside the skin the field is the foam's own (seeds in cubes of the
// infill's cell, struts of the thickness' diameter); the part meshes printable.
TEST(VoronoiFoam, AnInfillOfFoamKeepsASkinAndMeshesPrintable) {
  registerVolumeSources();
  const NodePtr part = testing::box({0, 0, 0}, {3, 2.5, 2});
  const Program infill = compile(makeNode("infill",
                                          {{"lattice", textValue("voronoi_struts")},
                                           {"wall", realValue(0.15)},
                                           {"cell", realValue(0.6)},
                                           {"thickness", realValue(0.1)}},
                                          {part}));
  const Program struts = compile(foam({0.6, 0.6, 0.6}, 0.05, 0.0, 1, 5));
  const Program f = compile(part);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> x(0, 3), y(0, 2.5), z(0, 2);
  int inside = 0, skin = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 q{x(rng), y(rng), z(rng)};
    const double depth = f.eval(q[0], q[1], q[2]), value = infill.eval(q[0], q[1], q[2]);
    if (depth > 0.0 && depth < 0.14) {
      EXPECT_GT(value, 0.0);
      ++skin;
    } else if (depth > 0.2) {
      EXPECT_NEAR(value, std::max(struts.eval(q[0], q[1], q[2]), 0.15 - depth), 1e-12);
      ++inside;
    }
  }
  EXPECT_GT(skin, 300);
  EXPECT_GT(inside, 1000);
  MeshingOptions o;
  o.bbox = {{-0.1, -0.1, -0.1}, {3.1, 2.6, 2.1}};
  o.resolution = 0.025;
  const CheckReport report = checkMesh(polygonize(infill, o));
  EXPECT_TRUE(report.printable());
  EXPECT_LT(report.volume, 0.6 * 3 * 2.5 * 2);
}

// The foam as a 3MF beam lattice clipped by a ball: lib3mf reads every beam back; every edge
// with its middle in the ball is a beam, none that keeps away from it; struts meeting at a
// node share its vertex (copies of a node across the tile's faces too).
TEST(VoronoiFoam, BeamLatticeThreeMfReadsBackWithEveryEdge) {
  const std::string path = ::testing::TempDir() + "/foam_beams.3mf";
  const NodePtr cut =
      makeNode("intersection", {}, {foam({0.5, 0.5, 0.5}, 0.04), testing::sphere(1.5)});
  const MeshingBox box{{{-1.6, -1.6, -1.6}, {1.6, 1.6, 1.6}}, 0.03};
  const BeamExportResult r =
      exportBeamLattice(cut, box, MeshSettings(), ThreeMfOptions(), "ball", path, false);
  ASSERT_TRUE(r.written);
  EXPECT_EQ(read3mfBeams(path).beams, r.beams);
  VoronoiFoamSettings s;
  s.cell = {0.5, 0.5, 0.5};
  s.seed = 3;
  s.tile = 4;
  const VoronoiFoamNetwork net = voronoiFoamNetwork(s);
  std::size_t inside = 0, reaching = 0;
  for (int i = -2; i <= 1; ++i)
    for (int j = -2; j <= 1; ++j)
      for (int k = -2; k <= 1; ++k)
        for (const StrutPiece& e : net.edges) {
          const Vec3 a = shifted(e.a, net.period, i, j, k), b = shifted(e.b, net.period, i, j, k);
          if (vlength(vscale(vadd(a, b), 0.5)) < 1.5) ++inside;
          if (distanceToSegment({0, 0, 0}, a, b) < 1.5 + 0.04 + 0.05) ++reaching;
        }
  EXPECT_GE(r.beams, inside);
  EXPECT_LE(r.beams, reaching);
  EXPECT_GT(inside, 300u);
  // four struts meet at a node: about half as many vertices as beams (more at the ball's
  // face, where a node keeps some of its struts)
  EXPECT_LT(r.vertices, r.beams * 3 / 4);
  std::remove(path.c_str());
}

TEST(VoronoiFoam, BadParametersAreNamed) {
  try {
    compile(foam({1, 1, 5}, 0.1));
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'cell'"), std::string::npos) << e.what();
  }
  try {  // two short sides: 8 x 32 x 32 seeds a period
    compile(foam({1, 0.25, 0.25}, 0.05, 0.0, 1, 8));
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'tile'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("8192 seeds"), std::string::npos) << e.what();
  }
  for (auto [name, value] : std::vector<std::pair<std::string, double>>{{"tile", 3},
                                                                        {"tile", 9},
                                                                        {"jitter", 1.5},
                                                                        {"blend", 0.6},
                                                                        {"blend", -0.1},
                                                                        {"radius", 0},
                                                                        {"seed", -1}}) {
    registerVolumeSources();
    try {
      NodePtr n = foam({1, 1, 1}, 0.1);
      auto params = n->params;
      params[name] = realValue(value);
      compile(makeNode("voronoi_foam", params, {}));
      FAIL() << name << " = " << value << ": no error";
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find("'" + name + "'"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace frep

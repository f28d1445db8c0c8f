// Strut lattices (frep/node_types_struts.cpp, frep/strut_cells.h): the field against the
// distance to every strut of the cells round the point, each unit cell meshed printable, a
// graded radius, and a program whose size does not grow with the cells a part spans.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <set>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "frep/node_helpers.h"
#include "frep/strut_cells.h"
#include "frep/tree.h"
#include "io/mesh_3mf.h"
#include "lattice/ffd_lattice.h"
#include "lattice_samples.h"
#include "mesh/mesher.h"
#include "pipeline/beam_export.h"
#include "test_nodes.h"

namespace frep {
namespace {

NodePtr lattice(const std::string& cell, Vec3 size, double radius, double nodeRadius = 0.0,
                Vec3 origin = {0, 0, 0}, std::vector<NodePtr> inputs = {}) {
  return makeNode("strut_lattice",
                  {{"cell_type", textValue(cell)},
                   {"cell", vec3Value(size)},
                   {"radius", realValue(radius)},
                   {"node_radius", realValue(nodeRadius)},
                   {"origin", vec3Value(origin)}},
                  std::move(inputs));
}

double kPiTimes(double r2) {
  return 3.14159265358979323846 * r2;
}

double segmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 e = vsub(b, a), d = vsub(p, a);
  const double l2 = vdot(e, e);
  const double t = l2 > 0 ? std::clamp(vdot(d, e) / l2, 0.0, 1.0) : 0.0;
  return vlength(vsub(d, vscale(e, t)));
}

// The distance from p to the struts (or nodes) of the 5 x 5 x 5 cells round p's own: every
// strut of the lattice copied into those cells, no folding.
struct BruteForce {
  double struts, nodes;
};
BruteForce bruteForce(const UnitCell& cell, const Vec3& size, const Vec3& origin, const Vec3& p) {
  int own[3];
  for (int a = 0; a < 3; ++a) own[a] = static_cast<int>(std::floor((p[a] - origin[a]) / size[a]));
  BruteForce best{HUGE_VAL, HUGE_VAL};
  auto world = [&](const Vec3& u, int i, int j, int k) {
    return Vec3{origin[0] + (u[0] + i) * size[0], origin[1] + (u[1] + j) * size[1],
                origin[2] + (u[2] + k) * size[2]};
  };
  for (int i = own[0] - 2; i <= own[0] + 2; ++i)
    for (int j = own[1] - 2; j <= own[1] + 2; ++j)
      for (int k = own[2] - 2; k <= own[2] + 2; ++k) {
        for (const UnitStrut& s : cell.struts)
          best.struts =
              std::min(best.struts, segmentDistance(p, world(s.a, i, j, k), world(s.b, i, j, k)));
        for (const Vec3& n : cell.nodes)
          best.nodes = std::min(best.nodes, vlength(vsub(p, world(n, i, j, k))));
      }
  return best;
}

// The figure: at 10,000 random points the field is radius minus the distance to the
// nearest strut within 1e-9, for every unit cell, with a cube cell, and with a cell of three
// sizes moved off the origin and node spheres.
TEST(StrutLattice, TheDistanceToTheNearestStrutAtTenThousandPoints) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (const UnitCell& cell : unitCells()) {
    for (int variant = 0; variant < 2; ++variant) {
      const Vec3 size = variant ? Vec3{0.9, 0.6, 1.3} : Vec3{1, 1, 1};
      const Vec3 origin = variant ? Vec3{0.17, -0.4, 2.3} : Vec3{0, 0, 0};
      const double radius = 0.07, nodeRadius = variant ? 0.12 : 0.0;
      const Program p = compile(lattice(cell.id, size, radius, nodeRadius, origin));
      double worst = 0.0;
      for (int i = 0; i < 5000; ++i) {
        const Vec3 q{u(rng), u(rng), u(rng)};
        const BruteForce b = bruteForce(cell, size, origin, q);
        double exact = radius - b.struts;
        if (nodeRadius > 0) exact = std::max(exact, nodeRadius - b.nodes);
        worst = std::max(worst, std::abs(p.eval(q[0], q[1], q[2]) - exact));
      }
      EXPECT_LT(worst, 1e-9) << cell.id << (variant ? ", cell of three sizes, node spheres" : "");
    }
  }
}

// Smooth joints: at random points the field is radius - the smooth minimum (m - k/2 +
// k / (2 sum max(0, 1 - (d - m) / k)^2)) of the distances to every strut of the cells round
// the point, brute force; exact where no other strut is within the blend of the nearest, and
// a blended lattice meshes printable with more solid at its joints.
TEST(StrutLattice, SmoothJointsAreTheSmoothMinimumOfEveryStrut) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const double radius = 0.06, blend = 0.08;
  for (const UnitCell& cell : unitCells()) {
    const Vec3 size = cell.id == "diamond" ? Vec3{1, 1, 1} : Vec3{0.9, 1.0, 1.2};
    const Program p = compile(makeNode("strut_lattice",
                                       {{"cell_type", textValue(cell.id)},
                                        {"cell", vec3Value(size)},
                                        {"radius", realValue(radius)},
                                        {"blend", realValue(blend)}},
                                       {}));
    double worst = 0.0;
    int exactPoints = 0, blendedPoints = 0;
    for (int i = 0; i < 1500; ++i) {
      const Vec3 q{u(rng), u(rng), u(rng)};
      // every strut once (a cell's list may repeat a strut its neighbour lists: Kelvin's)
      std::set<std::array<long long, 6>> seen;
      std::vector<double> d;
      int own[3];
      for (int a = 0; a < 3; ++a) own[a] = int(std::floor(q[a] / size[a]));
      for (int x = own[0] - 2; x <= own[0] + 2; ++x)
        for (int y = own[1] - 2; y <= own[1] + 2; ++y)
          for (int z = own[2] - 2; z <= own[2] + 2; ++z)
            for (const UnitStrut& s : cell.struts) {
              auto key = [&](const Vec3& c) {  // in 1e-9 of a cell
                return std::array<long long, 3>{std::llround((c[0] + x) * 1e9),
                                                std::llround((c[1] + y) * 1e9),
                                                std::llround((c[2] + z) * 1e9)};
              };
              std::array<long long, 3> ka = key(s.a), kb = key(s.b);
              if (kb < ka) std::swap(ka, kb);
              if (!seen.insert({ka[0], ka[1], ka[2], kb[0], kb[1], kb[2]}).second) continue;
              auto world = [&](const Vec3& c) {
                return Vec3{(c[0] + x) * size[0], (c[1] + y) * size[1], (c[2] + z) * size[2]};
              };
              d.push_back(segmentDistance(q, world(s.a), world(s.b)));
            }
      std::sort(d.begin(), d.end());
      const double m = d[0];
      double sum = 0.0;
      for (double di : d) sum += std::pow(std::max(0.0, 1.0 - (di - m) / blend), 2);
      const double smooth = m - 0.5 * blend + 0.5 * blend / sum;
      const double value = p.eval(q[0], q[1], q[2]);
      worst = std::max(worst, std::abs(value - (radius - smooth)));
      if (d.size() > 1 && d[1] - m >= blend) {
        EXPECT_NEAR(value, radius - m, 1e-9) << cell.id << ": not exact away from the joints";
        ++exactPoints;
      } else if (d[1] - m < 0.5 * blend) {  // a joint's fillet: more solid
        EXPECT_GT(value, radius - m + 1e-4) << cell.id;
        ++blendedPoints;
      }
    }
    EXPECT_LT(worst, 1e-9) << cell.id;
    EXPECT_GT(exactPoints, 100) << cell.id;
    EXPECT_GT(blendedPoints, 50) << cell.id;
  }
  // printable, and the joints' fillets add solid
  double volumes[2];
  for (int blended = 0; blended < 2; ++blended) {
    const NodePtr part = makeNode("intersection", {},
                                  {makeNode("strut_lattice",
                                            {{"cell_type", textValue("octet")},
                                             {"cell", vec3Value({1, 1, 1})},
                                             {"radius", realValue(0.06)},
                                             {"blend", realValue(blended ? 0.1 : 0.0)}},
                                            {}),
                                   testing::box({-0.9, -0.9, -0.9}, {2.0, 2.0, 2.0})});
    MeshingOptions o;
    o.bbox = {{-1.0, -1.0, -1.0}, {1.2, 1.2, 1.2}};
    o.resolution = 0.03;
    const CheckReport report = checkMesh(polygonize(compile(part), o));
    EXPECT_TRUE(report.printable()) << (blended ? "blended" : "sharp");
    volumes[blended] = report.volume;
  }
  EXPECT_GT(volumes[1], 1.02 * volumes[0]);
}

// Cells that follow a cylinder: a turn of the axis by one cell's angle leaves the lattice as it
// was, the angle's cut is seamless, the nodes lie where the cylinder's coordinates put them, a
// tube meshes printable, and a beam 3MF (straight beams) is refused naming why.
// A conformal lattice's beam 3MF (`model`: the struts' field `lattice` cut to `part`): read
// back by lib3mf with the beam count written; every beam's ends on a strut's curved axis (the
// lattice's field there its radius, within `farthestEnd`: more where a chain is chained again)
// and its middle within `farthestMiddle` of it in the field
// (the chain keeps within a tenth of the radius of the curve in the world; the field's
// coordinates stretch that); and every point of a strut deep in the part within `widest` (the
// struts' widest world radius) and the chain's tolerance of a beam. Points `nearAxis` gives
// are left out (round a cylinder's axis cells meet in a line and narrow).
void expectBeamsFollowTheCurvedStruts(const NodePtr& model, const NodePtr& lattice,
                                      const NodePtr& part, const Box3& box, double radius,
                                      double widest, double farthestMiddle,
                                      const std::function<bool(const Vec3&)>& nearAxis,
                                      double farthestEnd = 1e-3) {
  const std::string path = ::testing::TempDir() + "/conformal.3mf";
  const BeamExportResult r = exportBeamLattice(model, {box, 0.05}, MeshSettings(), ThreeMfOptions(),
                                               "conformal", path, false);
  ASSERT_TRUE(r.written);
  const ThreeMfBeams back = read3mfBeams(path);
  EXPECT_EQ(back.beams, r.beams);
  EXPECT_GT(back.beams, 500u);
  const Program struts = compile(lattice), inside = compile(part);
  auto field = [&](const Vec3& p) {
    return nearAxis(p) ? HUGE_VAL : struts.eval(p[0], p[1], p[2]);
  };
  double lowestEnd = HUGE_VAL, lowestMiddle = HUGE_VAL;
  for (const auto& e : back.ends) {
    const Vec3 a{e[0][0], e[0][1], e[0][2]}, b{e[1][0], e[1][1], e[1][2]};
    // (a thousandth of the beam in from its ends: a bent strut's piece ends on the bent
    // lattice's boundary, where the field may take the point as outside it)
    const Vec3 d = vsub(b, a);
    lowestEnd =
        std::min({lowestEnd, field(vadd(a, vscale(d, 1e-3))), field(vadd(a, vscale(d, 1 - 1e-3)))});
    lowestMiddle = std::min(lowestMiddle, field(vscale(vadd(a, b), 0.5)));
  }
  EXPECT_GT(lowestEnd, radius - farthestEnd);
  EXPECT_GT(lowestMiddle, radius - farthestMiddle);
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> x(box.lo[0], box.hi[0]), y(box.lo[1], box.hi[1]),
      z(box.lo[2], box.hi[2]);
  int covered = 0;
  for (int i = 0; i < 4000 && covered < 300; ++i) {
    const Vec3 q{x(rng), y(rng), z(rng)};
    if (inside.eval(q[0], q[1], q[2]) < 2 * widest || struts.eval(q[0], q[1], q[2]) < 0.0) continue;
    double nearest = HUGE_VAL;
    for (const auto& e : back.ends)
      nearest = std::min(
          nearest, segmentDistance(q, {e[0][0], e[0][1], e[0][2]}, {e[1][0], e[1][1], e[1][2]}));
    EXPECT_LT(nearest, widest + 0.1 * radius + 1e-5) << q[0] << "," << q[1] << "," << q[2];
    ++covered;
  }
  EXPECT_GT(covered, 50);
  std::remove(path.c_str());
}

// A lattice of cells of (1, 1.2, 0.8) and struts of 0.08 following a cylinder or a sphere.
NodePtr conformalLattice(const std::string& cell, const std::string& conform, const Vec3& origin,
                         const Vec3& axis, int around) {
  return makeNode("strut_lattice",
                  {{"cell_type", textValue(cell)},
                   {"cell", vec3Value({1, 1.2, 0.8})},
                   {"radius", realValue(0.08)},
                   {"origin", vec3Value(origin)},
                   {"conform", textValue(conform)},
                   {"axis", vec3Value(axis)},
                   {"around", realValue(around)}},
                  {});
}

TEST(StrutLattice, ConformalToACylinder) {
  const Vec3 axis = vscale(Vec3{1, 2, 2}, 1.0 / 3.0), origin{0.5, -1, 2};
  const int around = 10;
  auto conformal = [&](const std::string& cell) {
    return conformalLattice(cell, "cylinder", origin, axis, around);
  };
  // the node's frame round the axis (u, v across it; angles from u)
  const Frame frame = frameAlong(axis);
  const Vec3 u = frame.u, v = frame.v;
  auto at = [&](double rho, double angle, double h) {
    return vadd(origin, vadd(vscale(u, rho * std::cos(angle)),
                             vadd(vscale(v, rho * std::sin(angle)), vscale(axis, h))));
  };
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> rho(0.3, 4), angle(-3.2, 3.2), h(-2, 2);
  for (const char* cell : {"octet", "simple_cubic"}) {
    const Program p = compile(conformal(cell));
    double turned = 0.0;
    for (int i = 0; i < 2000; ++i) {
      const double r = rho(rng), a = angle(rng), z = h(rng);
      const Vec3 q = at(r, a, z), w = at(r, a + 2 * 3.14159265358979323846 / around, z);
      turned = std::max(turned, std::abs(p.eval(q[0], q[1], q[2]) - p.eval(w[0], w[1], w[2])));
    }
    EXPECT_LT(turned, 1e-9) << cell;
    // across the angle's cut (the far side from u): no seam
    double seam = 0.0;
    for (int i = 0; i < 200; ++i) {
      const double r = rho(rng), z = h(rng);
      const Vec3 q = at(r, 3.14159265358979323846 - 1e-9, z),
                 w = at(r, -3.14159265358979323846 + 1e-9, z);
      seam = std::max(seam, std::abs(p.eval(q[0], q[1], q[2]) - p.eval(w[0], w[1], w[2])));
    }
    EXPECT_LT(seam, 1e-6) << cell;
  }
  // simple cubic: the radial strut 3 cells round and 1 cell up runs straight out from the
  // axis (on it, the field is the radius); half a cell round beside it, nothing
  const Program cubic = compile(conformal("simple_cubic"));
  const double cellAngle = 2 * 3.14159265358979323846 / around;
  for (double r : {1.3, 2.5, 3.7}) {
    const Vec3 on = at(r, 3 * cellAngle, 0.8), off = at(r, 3.5 * cellAngle, 0.8);
    EXPECT_NEAR(cubic.eval(on[0], on[1], on[2]), 0.08, 1e-9) << r;
    EXPECT_LT(cubic.eval(off[0], off[1], off[2]), 0.0) << r;
  }
  // a tube of it meshes printable, and its beam 3MF follows the curved struts: a cell's y
  // side is its arc at 12 / (2 pi) = 1.91 from the axis, so a strut is up to 3 / 1.91 times
  // wider at the tube's outside (radius 3)
  const NodePtr round = makeNode("strut_lattice",
                                 {{"cell_type", textValue("octet")},
                                  {"cell", vec3Value({1, 1, 1})},
                                  {"radius", realValue(0.08)},
                                  {"conform", textValue("cylinder")},
                                  {"around", realValue(12)}},
                                 {});
  const NodePtr ring = makeNode(
      "difference", {},
      {makeNode("cylinder", {{"radius", realValue(3.0)}, {"length", realValue(2.0)}}, {}),
       makeNode("cylinder", {{"radius", realValue(1.5)}, {"length", realValue(3.0)}}, {})});
  MeshingOptions o;
  o.bbox = {{-3.2, -3.2, -1.2}, {3.2, 3.2, 1.2}};
  o.resolution = 0.03;
  EXPECT_TRUE(
      checkMesh(polygonize(compile(makeNode("intersection", {}, {round, ring})), o)).printable());
  const double scale = 12 / (2 * 3.14159265358979323846);
  expectBeamsFollowTheCurvedStruts(makeNode("intersection", {}, {round, ring}), round, ring, o.bbox,
                                   0.08, 0.08 * 3 / scale, 0.1 * 0.08 * scale,
                                   [](const Vec3& p) { return std::hypot(p[0], p[1]) < 1.0; });
}

TEST(StrutLattice, ConformalToASphere) {
  const double pi = 3.14159265358979323846;
  const Vec3 axis = vscale(Vec3{2, -1, 2}, 1.0 / 3.0), origin{0.5, -1, 2};
  const int around = 16;
  auto conformal = [&](const std::string& cell) {
    return conformalLattice(cell, "sphere", origin, axis, around);
  };
  // the node's frame round the polar axis (u, v across it; longitudes from u)
  const Frame frame = frameAlong(axis);
  auto at = [&](double r, double longitude, double fromPole) {
    const double across = r * std::sin(fromPole);
    return vadd(origin, vadd(vscale(frame.u, across * std::cos(longitude)),
                             vadd(vscale(frame.v, across * std::sin(longitude)),
                                  vscale(axis, r * std::cos(fromPole)))));
  };
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> radius(0.5, 4), longitude(-3.2, 3.2), polar(0.2, 2.9);
  for (const char* cell : {"octet", "simple_cubic"}) {
    const Program p = compile(conformal(cell));
    double turned = 0.0, seam = 0.0;
    for (int i = 0; i < 2000; ++i) {
      const double r = radius(rng), a = longitude(rng), t = polar(rng);
      const Vec3 q = at(r, a, t), w = at(r, a + 2 * pi / around, t);
      turned = std::max(turned, std::abs(p.eval(q[0], q[1], q[2]) - p.eval(w[0], w[1], w[2])));
    }
    for (int i = 0; i < 200; ++i) {  // across the longitude's cut: no seam
      const double r = radius(rng), t = polar(rng);
      const Vec3 q = at(r, pi - 1e-9, t), w = at(r, -pi + 1e-9, t);
      seam = std::max(seam, std::abs(p.eval(q[0], q[1], q[2]) - p.eval(w[0], w[1], w[2])));
    }
    EXPECT_LT(turned, 1e-9) << cell;
    EXPECT_LT(seam, 1e-6) << cell;
  }
  // simple cubic: a strut runs straight out from the centre at every whole cell of longitude
  // and of latitude (on it, the field is the radius); half a cell of latitude beside it, none
  const Program cubic = compile(conformal("simple_cubic"));
  const double cellAngle = 2 * pi / around;  // a cell's arc, in both directions, in radians
  for (double r : {1.3, 2.5, 3.7}) {
    const Vec3 on = at(r, 3 * cellAngle, 2 * cellAngle),
               off = at(r, 3 * cellAngle, 2.5 * cellAngle);
    EXPECT_NEAR(cubic.eval(on[0], on[1], on[2]), 0.08, 1e-9) << r;
    EXPECT_LT(cubic.eval(off[0], off[1], off[2]), 0.0) << r;
  }
  // a spherical shell of it meshes printable
  const NodePtr shell =
      makeNode("intersection", {},
               {makeNode("strut_lattice",
                         {{"cell_type", textValue("octet")},
                          {"cell", vec3Value({1, 1, 1})},
                          {"radius", realValue(0.08)},
                          {"conform", textValue("sphere")},
                          {"around", realValue(16)}},
                         {}),
                makeNode("difference", {},
                         {makeNode("sphere", {{"radius", realValue(3.0)}}, {}),
                          makeNode("sphere", {{"radius", realValue(2.0)}}, {})})});
  MeshingOptions o;
  o.bbox = {{-3.2, -3.2, -3.2}, {3.2, 3.2, 3.2}};
  o.resolution = 0.04;
  const TriangleMesh mesh = polygonize(compile(shell), o);
  EXPECT_GT(mesh.triangleCount(), 10000u);
  EXPECT_TRUE(checkMesh(mesh).printable());
  // its beam 3MF follows the curved struts (a cell's sides are arcs at 16 / (2 pi) = 2.55)
  const double scale = 16 / (2 * pi);
  expectBeamsFollowTheCurvedStruts(shell, shell->inputs[0], shell->inputs[1], o.bbox, 0.08,
                                   0.08 * 3 / scale, 0.1 * 0.08 * scale,
                                   [](const Vec3& p) { return std::hypot(p[0], p[1]) < 1.0; });
}

// Each unit cell meshes printable at three resolutions, cut to a block of 2 x 2 x 2 cells, with
// struts in every cell (about the volume the cell's struts make).
TEST(StrutLattice, EveryUnitCellMeshesPrintableAtThreeResolutions) {
  for (const UnitCell& cell : unitCells()) {
    const NodePtr part = makeNode(
        "intersection", {},
        {lattice(cell.id, {1, 1, 1}, 0.08), testing::box({-0.9, -0.9, -0.9}, {2.0, 2.0, 2.0})});
    const Program p = compile(part);
    double volumes[3];
    int r = 0;
    for (double h : {0.05, 0.035, 0.025}) {
      MeshingOptions o;
      o.bbox = {{-1.0, -1.0, -1.0}, {1.2, 1.2, 1.2}};
      o.resolution = h;
      const CheckReport report = checkMesh(polygonize(p, o));
      EXPECT_TRUE(report.printable()) << cell.id << " at " << h;
      volumes[r++] = report.volume;
    }
    // the finer meshes agree on the volume (the struts are resolved, not lost between points)
    EXPECT_NEAR(volumes[1], volumes[2], 0.03 * volumes[2]) << cell.id;
    EXPECT_GT(volumes[2], 0.02) << cell.id;
  }
}

// A graded lattice: the input's value is the radius point by point.
TEST(StrutLattice, AFieldInputGradesTheRadius) {
  const NodePtr radius = makeNode(
      "formula", {{"formula", textValue("0.05 + 0.02 * x")}, {"parameters", textValue("")}}, {});
  const Program p = compile(lattice("octet", {1, 1, 1}, 0.1, 0.0, {0, 0, 0}, {radius}));
  const UnitCell& cell = unitCell("octet");
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 q{u(rng), u(rng), u(rng)};
    const double exact = 0.05 + 0.02 * q[0] - bruteForce(cell, {1, 1, 1}, {0, 0, 0}, q).struts;
    EXPECT_NEAR(p.eval(q[0], q[1], q[2]), exact, 1e-9);
  }
  // thicker struts where x is larger: a cell further along x, the same place in it, 0.02 more
  EXPECT_NEAR(p.eval(1.08, 0.5, 0.5) - p.eval(0.08, 0.5, 0.5), 0.02, 1e-12);
}

// The field's program is the struts of one small domain, whatever the cells a part spans and
// whatever their size: nothing per cell in memory, one instruction a strut (its squared
// distance) and a few dozen in all (diamond the most: folded round a node in a cube cell, by
// translation only in a cell of three sizes).
TEST(StrutLattice, TheProgramIsSmallForAnyCell) {
  for (const UnitCell& cell : unitCells())
    for (double size : {1.0, 0.01, 37.0}) {
      const std::size_t cube =
          compile(lattice(cell.id, {size, size, size}, 0.1 * size)).instructionCount();
      const std::size_t uneven =
          compile(lattice(cell.id, {size, size, 0.8 * size}, 0.1 * size)).instructionCount();
      EXPECT_LT(cube, cell.mirrorSymmetric ? 50u : 100u) << cell.id;
      EXPECT_LT(uneven, cell.mirrorSymmetric ? 50u : 1000u) << cell.id;
    }
}

// Infill with struts: a block with a hole through it, hollowed to a skin (round the hole too)
// and filled with octet struts of the thickness' diameter; the inside is the strut lattice's
// own field, and the part meshes printable.
TEST(StrutLattice, AnInfillOfStrutsKeepsASkinRoundThePartAndItsHole) {
  const NodePtr part =
      makeNode("difference", {},
               {testing::box({0, 0, 0}, {4, 3, 2}), makeNode("cylinder",
                                                             {{"center", vec3Value({2, 1.5, 1})},
                                                              {"radius", realValue(0.6)},
                                                              {"length", realValue(3)}},
                                                             {})});
  const Program infill = compile(makeNode("infill",
                                          {{"lattice", textValue("octet_struts")},
                                           {"wall", realValue(0.15)},
                                           {"cell", realValue(0.5)},
                                           {"thickness", realValue(0.08)}},
                                          {part}));
  const Program struts = compile(lattice("octet", {0.5, 0.5, 0.5}, 0.04));
  const Program f = compile(part);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> x(0, 4), y(0, 3), z(0, 2);
  int inside = 0, skin = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 q{x(rng), y(rng), z(rng)};
    const double depth = f.eval(q[0], q[1], q[2]), value = infill.eval(q[0], q[1], q[2]);
    if (depth > 0.0 && depth < 0.14) {  // in the skin (the hole's too): solid
      EXPECT_GT(value, 0.0);
      ++skin;
    } else if (depth > 0.16 + 0.04) {  // inside: the struts, wherever the skin is not nearer
      EXPECT_NEAR(value, std::max(struts.eval(q[0], q[1], q[2]), 0.15 - depth), 1e-12);
      ++inside;
    }
  }
  EXPECT_GT(skin, 300);
  EXPECT_GT(inside, 1000);
  MeshingOptions o;
  o.bbox = {{-0.1, -0.1, -0.1}, {4.1, 3.1, 2.1}};
  o.resolution = 0.02;
  const CheckReport report = checkMesh(polygonize(infill, o));
  EXPECT_TRUE(report.printable());
  // lighter than the block; thicker struts weigh more
  const double solid = 4 * 3 * 2 - kPiTimes(0.36) * 2;
  EXPECT_LT(report.volume, 0.7 * solid);
  const Program thicker = compile(makeNode("infill",
                                           {{"lattice", textValue("octet_struts")},
                                            {"wall", realValue(0.15)},
                                            {"cell", realValue(0.5)},
                                            {"thickness", realValue(0.12)}},
                                           {part}));
  EXPECT_GT(checkMesh(polygonize(thicker, o)).volume, report.volume + 1.0);
}

// A conformal lattice: a beam of octet cells whose cells follow an FFD bend (the FFD node
// over the strut lattice: struts curved with their cells), and a graded octet whose radius
// grows along the beam; both mesh printable, and the bent one lies where the bend puts it.
TEST(StrutLattice, ConformalThroughAnFfdBendAndGradedExportPrintable) {
  const NodePtr beam = makeNode(
      "intersection", {},
      {lattice("octet", {0.5, 0.5, 0.5}, 0.05, 0.07), testing::box({-2, -0.5, -0.5}, {4, 1, 1})});
  // a parabola: the ends 1 up
  const FfdLattice bend = testing::parabolaLattice({{-2.05, -0.55, -0.55}, {2.05, 0.55, 0.55}});
  const NodePtr conformal = makeNode("ffd", testing::ffdParams(bend), {beam});
  auto nowhere = [](const Vec3&) { return false; };
  MeshingOptions o;
  o.bbox = {{-2.2, -0.7, -0.7}, {2.2, 0.7, 1.8}};
  o.resolution = 0.025;
  const TriangleMesh bent = polygonize(compile(conformal), o);
  const CheckReport r = checkMesh(bent);
  EXPECT_TRUE(r.printable());
  double top = -HUGE_VAL;
  for (const Vec3f& v : bent.positions)
    if (std::abs(v[0]) > 1.9) top = std::max(top, double(v[2]));
  EXPECT_GT(top, 1.2);  // the ends bent up with their cells
  // as a beam 3MF, the bent beam's struts chains of beams along their curves, whether the
  // ffd bends the lattice cut to the part or the lattice alone, cut to a part
  const NodePtr bentStruts =
      makeNode("ffd", testing::ffdParams(bend), {lattice("octet", {0.5, 0.5, 0.5}, 0.05, 0.07)});
  const NodePtr bentPart =
      makeNode("ffd", testing::ffdParams(bend), {testing::box({-2, -0.5, -0.5}, {4, 1, 1})});
  expectBeamsFollowTheCurvedStruts(conformal, bentStruts, bentPart, o.bbox, 0.05, 0.05 * 1.5, 0.02,
                                   nowhere);
  expectBeamsFollowTheCurvedStruts(makeNode("intersection", {}, {bentStruts, bentPart}), bentStruts,
                                   bentPart, o.bbox, 0.05, 0.05 * 1.5, 0.02, nowhere);
  const NodePtr radius = makeNode(
      "formula", {{"formula", textValue("0.03 + 0.015 * (x + 2)")}, {"parameters", textValue("")}},
      {});
  const NodePtr graded =
      makeNode("intersection", {},
               {lattice("octet", {0.5, 0.5, 0.5}, 0.05, 0.0, {0, 0, 0}, {radius}),
                testing::box({-2, -0.5, -0.5}, {4, 1, 1})});
  // the graded lattice bent: each beam's radius is the field's where its end came from (the
  // bend moves points only up and down, so there x is the world's x); read in the world
  // instead, the radii would miss by up to the field's change over the 1 the ends rise
  const std::string gradedPath = ::testing::TempDir() + "/graded.3mf";
  const BeamExportResult gb = exportBeamLattice(
      makeNode("intersection", {},
               {makeNode("ffd", testing::ffdParams(bend), {graded->inputs[0]}), bentPart}),
      {o.bbox, 0.05}, MeshSettings(), ThreeMfOptions(), "graded", gradedPath, false);
  ASSERT_TRUE(gb.written);
  const ThreeMfBeams gback = read3mfBeams(gradedPath);
  ASSERT_EQ(gback.beams, gb.beams);
  ASSERT_EQ(gback.radii.size(), gback.beams);
  ASSERT_GT(gback.beams, 100u);
  double thinnest = HUGE_VAL, thickest = 0.0;
  for (std::size_t i = 0; i < gback.beams; ++i)
    for (int e = 0; e < 2; ++e) {
      const double x = gback.ends[i][e][0], r = gback.radii[i][e];
      EXPECT_NEAR(r, 0.03 + 0.015 * (x + 2.0), 1e-5) << "beam " << i << " end " << e;
      thinnest = std::min(thinnest, r), thickest = std::max(thickest, r);
    }
  EXPECT_GT(thickest, 1.5 * thinnest);
  // the other way round: the graded lattice bent, then cut to the bent part
  const BeamExportResult gb2 =
      exportBeamLattice(makeNode("ffd", testing::ffdParams(bend), {graded}), {o.bbox, 0.05},
                        MeshSettings(), ThreeMfOptions(), "graded", gradedPath, false);
  EXPECT_EQ(gb2.beams, gb.beams);
  o.bbox = {{-2.1, -0.6, -0.6}, {2.1, 0.6, 0.6}};
  const TriangleMesh g = polygonize(compile(graded), o);
  EXPECT_TRUE(checkMesh(g).printable());
  // more material at the thick end: the solid's share of random points there
  const Program field = compile(graded);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> across(-0.5, 0.5), along(1.0, 2.0);
  int thin = 0, thick = 0;
  for (int i = 0; i < 20000; ++i) {
    const double x = along(rng), y = across(rng), z = across(rng);
    thick += field.eval(x, y, z) > 0;
    thin += field.eval(-x, y, z) > 0;
  }
  EXPECT_GT(thick, 1.3 * thin);
}

// Cells conformal to a cylinder and then bent by an FFD: a tube of octet cells round the x
// axis, lifted along a parabola. As beams, each strut is chained twice (round the cylinder,
// then through the bend), and the beams follow the twice-curved struts.
TEST(StrutLattice, CellsConformalToACylinderAndBentExportAsBeams) {
  const FfdLattice bend = testing::parabolaLattice({{-2.1, -1.1, -1.1}, {2.1, 1.1, 1.1}});
  const NodePtr tube = makeNode(
      "difference", {},
      {makeNode(
           "cylinder",
           {{"axis", vec3Value({1, 0, 0})}, {"radius", realValue(1.0)}, {"length", realValue(4.0)}},
           {}),
       makeNode(
           "cylinder",
           {{"axis", vec3Value({1, 0, 0})}, {"radius", realValue(0.6)}, {"length", realValue(4.2)}},
           {})});
  const NodePtr cells = makeNode("strut_lattice",
                                 {{"cell_type", textValue("octet")},
                                  {"cell", vec3Value({0.3, 0.3, 0.3})},
                                  {"radius", realValue(0.03)},
                                  {"conform", textValue("cylinder")},
                                  {"axis", vec3Value({1, 0, 0})},
                                  {"around", realValue(20)}},
                                 {});
  const NodePtr bentCells = makeNode("ffd", testing::ffdParams(bend), {cells});
  const NodePtr bentTube = makeNode("ffd", testing::ffdParams(bend), {tube});
  const Box3 box{{-2.2, -1.2, -1.2}, {2.2, 1.2, 2.3}};
  // (the axis bent along about the parabola; the tube's hole is 0.6 round it)
  auto nearBentAxis = [](const Vec3& p) {
    return std::hypot(p[1], p[2] - 0.25 * p[0] * p[0]) < 0.45;
  };
  // the bend's chains run between points of the cylinder's chains, each within half the
  // tolerance (a twentieth of the radius) of its strut, stretched by the bend
  const double endsOff = 0.05 * 0.03 * 1.6;
  expectBeamsFollowTheCurvedStruts(makeNode("intersection", {}, {bentCells, bentTube}), bentCells,
                                   bentTube, box, 0.03, 0.03 * 1.6, 0.012, nearBentAxis, endsOff);
  expectBeamsFollowTheCurvedStruts(
      makeNode("ffd", testing::ffdParams(bend), {makeNode("intersection", {}, {cells, tube})}),
      bentCells, bentTube, box, 0.03, 0.03 * 1.6, 0.012, nearBentAxis, endsOff);
}

// The beam lattice 3MF: an octet lattice cut to a ball, its struts as beams clipped by the
// ball's mesh, read back by lib3mf: every strut whose middle lies in the ball is there, none
// that keeps away from it, and the file is a fraction of the meshed struts' 3MF.
TEST(StrutLattice, BeamLatticeThreeMfReadsBackWithEveryStrut) {
  const std::string dir = ::testing::TempDir();
  const NodePtr ball = testing::sphere(1.5);
  const NodePtr cut = makeNode("intersection", {}, {lattice("octet", {0.5, 0.5, 0.5}, 0.04), ball});
  const MeshingBox box{{{-1.6, -1.6, -1.6}, {1.6, 1.6, 1.6}}, 0.02};
  const std::string beamsPath = dir + "/beams.3mf";
  const BeamExportResult r =
      exportBeamLattice(cut, box, MeshSettings(), ThreeMfOptions(), "ball", beamsPath, false);
  ASSERT_TRUE(r.written);
  EXPECT_TRUE(r.clipReport.printable());
  const ThreeMfBeams back = read3mfBeams(beamsPath);
  EXPECT_EQ(back.beams, r.beams);
  EXPECT_EQ(back.clipped, 1u);
  // every strut of the cells round the ball, brute force: those with their middle inside must
  // be beams, those farther than their radius and a tenth of a cell from it must not (the
  // boxes the beams are chosen by reach a little beyond a strut)
  std::size_t inside = 0, reaching = 0;
  const UnitCell& cell = unitCell("octet");
  std::vector<std::pair<Vec3, Vec3>> seen;
  for (int i = -5; i <= 4; ++i)
    for (int j = -5; j <= 4; ++j)
      for (int k = -5; k <= 4; ++k)
        for (const UnitStrut& s : cell.struts) {
          Vec3 a = vscale(vadd(s.a, {double(i), double(j), double(k)}), 0.5);
          Vec3 b = vscale(vadd(s.b, {double(i), double(j), double(k)}), 0.5);
          if (b < a) std::swap(a, b);
          const Vec3 m = vscale(vadd(a, b), 0.5);
          if (vlength(m) < 1.5) ++inside;
          if (segmentDistance({0, 0, 0}, a, b) < 1.5 + 0.04 + 0.05) ++reaching;
        }
  EXPECT_GE(r.beams, inside);
  EXPECT_LE(r.beams, reaching);
  EXPECT_GT(inside, 500u);
  // the same part meshed, as a 3MF
  MeshingOptions o;
  o.bbox = box.box;
  o.resolution = box.resolution;
  const std::string meshedPath = dir + "/meshed.3mf";
  write3mf({{"ball", polygonize(compile(cut), o)}}, meshedPath);
  const auto beamsBytes = std::filesystem::file_size(beamsPath);
  const auto meshedBytes = std::filesystem::file_size(meshedPath);
  EXPECT_LT(3 * beamsBytes, meshedBytes) << beamsBytes << " against " << meshedBytes;
  std::remove(beamsPath.c_str());
  std::remove(meshedPath.c_str());
}

// An infill of struts: its skin a printed mesh, the struts beams ending in the middle of the
// skin (no clipping mesh), covering every strut inside; a model that is no strut lattice is
// refused, naming what --beams needs.
TEST(StrutLattice, BeamLatticeOfAnInfillAndWhatIsRefused) {
  const std::string path = ::testing::TempDir() + "/infill.3mf";
  const NodePtr infill = makeNode("infill",
                                  {{"lattice", textValue("kelvin_struts")},
                                   {"wall", realValue(0.1)},
                                   {"cell", realValue(0.5)},
                                   {"thickness", realValue(0.06)}},
                                  {testing::box({0, 0, 0}, {2, 1.5, 1})});
  const MeshingBox box{{{-0.1, -0.1, -0.1}, {2.1, 1.6, 1.1}}, 0.025};
  const BeamExportResult r =
      exportBeamLattice(infill, box, MeshSettings(), ThreeMfOptions(), "block", path, false);
  ASSERT_TRUE(r.written);
  EXPECT_TRUE(r.skinReport.printable());
  EXPECT_GT(r.skinTriangles, 1000u);
  // the skin simplified within a tenth of a cell unless a tolerance is given: a fraction of
  // the mesher's triangles for the block's walls
  EXPECT_DOUBLE_EQ(r.meshTolerance, 0.0025);
  EXPECT_NE(beamExportSummary(r).find("simplified within 0.0025"), std::string::npos)
      << beamExportSummary(r);
  MeshingOptions walls;
  walls.bbox = box.box;
  walls.resolution = box.resolution;
  const std::size_t meshers =
      polygonize(compile(makeNode("difference", {},
                                  {testing::box({0, 0, 0}, {2, 1.5, 1}),
                                   testing::box({0.1, 0.1, 0.1}, {1.9, 1.4, 0.9})})),
                 walls)
          .triangleCount();
  EXPECT_LT(r.skinTriangles, meshers / 4) << meshers;
  MeshSettings fine;
  fine.tolerance = 0.0002;
  const BeamExportResult finer =
      exportBeamLattice(infill, box, fine, ThreeMfOptions(), "block", path, false);
  EXPECT_DOUBLE_EQ(finer.meshTolerance, 0.0002);
  EXPECT_EQ(finer.beams, r.beams);
  const BeamExportResult again =
      exportBeamLattice(infill, box, MeshSettings(), ThreeMfOptions(), "block", path, false);
  EXPECT_EQ(again.skinTriangles, r.skinTriangles);
  const ThreeMfBeams back = read3mfBeams(path);
  EXPECT_EQ(back.beams, r.beams);
  EXPECT_FALSE(r.clipped);
  EXPECT_EQ(back.clipped, 0u);
  EXPECT_EQ(r.clipTriangles, 0u);
  // every beam's ends at least half the skin (0.05) deep in the block: caps of radius 0.03 in
  // the skin
  auto depth = [](const Vec3& p) {
    return std::min({p[0], 2 - p[0], p[1], 1.5 - p[1], p[2], 1 - p[2]});
  };
  for (const auto& ends : back.ends)
    for (const Vec3f& e : ends) EXPECT_GT(depth({e[0], e[1], e[2]}), 0.05 - 1e-5);
  // and the beams hold every strut deeper in: a point inside a strut is inside a beam
  const Program struts = compile(lattice("kelvin", {0.5, 0.5, 0.5}, 0.03));
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> x(0, 2), y(0, 1.5), z(0, 1);
  int covered = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 q{x(rng), y(rng), z(rng)};
    if (depth(q) < 0.1 || struts.eval(q[0], q[1], q[2]) < 1e-4) continue;
    double nearest = HUGE_VAL;
    for (const auto& ends : back.ends)
      nearest = std::min(nearest, segmentDistance(q, {ends[0][0], ends[0][1], ends[0][2]},
                                                  {ends[1][0], ends[1][1], ends[1][2]}));
    EXPECT_LT(nearest, 0.03 + 1e-5) << q[0] << "," << q[1] << "," << q[2];
    ++covered;
  }
  EXPECT_GT(covered, 20);
  const ThreeMfContents contents = read3mf(path);  // the build: the skin and the struts
  ASSERT_EQ(contents.objects.size(), 2u);
  EXPECT_EQ(contents.objects[0].mesh.triangles.size(), r.skinTriangles);
  EXPECT_TRUE(contents.objects[1].mesh.triangles.empty());
  std::remove(path.c_str());
  try {
    exportBeamLattice(testing::sphere(1), box, MeshSettings(), ThreeMfOptions(), "ball", path,
                      false);
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("strut_lattice"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(StrutLattice, BadParametersAreNamed) {
  try {  // a diamond cell much longer along one axis (folded by translation: too many struts)
    compile(lattice("diamond", {1, 1, 5}, 0.1));
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'cell'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at most 4 times"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(compile(lattice("octet", {1, 1, 5}, 0.1)));
  for (auto [name, value] :
       std::vector<std::pair<std::string, ParamValue>>{{"cell", vec3Value({1, 0, 1})},
                                                       {"radius", realValue(0)},
                                                       {"node_radius", realValue(-1)},
                                                       {"cell_type", textValue("hexagonal")}}) {
    std::map<std::string, ParamValue> params = {{name, value}};
    try {
      compile(makeNode("strut_lattice", params, {}));
      FAIL() << name << ": no error";
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace frep

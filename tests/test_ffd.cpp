// The ffd node and the lattice map behind it (lattice/ffd_map.h, frep/ffd_field.h): leaf
// bounds hold the lattice's image, the fast inverse finds every point and nothing outside,
// box covers are sound, and the deformed field is the input pulled back through the lattice.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "frep/bounds.h"
#include "frep/ffd_field.h"
#include "frep/program.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"
#include "lattice/ffd_map.h"
#include "lattice_samples.h"
#include "mesh/mesh_ffd.h"
#include "mesh/mesher.h"
#include "test_nodes.h"
#include "volume/field_sources.h"

namespace frep {
namespace {

using frep::testing::sphere;

using testing::kLatticeRest;
using testing::twistedLattice;

double distance(const Vec3& a, const Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

bool holds(const Box3& b, const Vec3& p) {
  for (int k = 0; k < 3; ++k)
    if (!(p[k] >= b.lo[k] && p[k] <= b.hi[k])) return false;
  return true;
}

Vec3 inside(const Box3& b, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Vec3 p;
  for (int k = 0; k < 3; ++k) p[k] = b.lo[k] + u(rng) * (b.hi[k] - b.lo[k]);
  return p;
}

bool same(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

struct Case {
  int l, m, n;
  double turns, jitter;
};
const Case kCases[] = {{2, 2, 2, 0.3, 0.1}, {4, 3, 5, 1.5, 0.25}, {3, 3, 8, 2.5, 0.2}};

TEST(FfdMap, LeafBoundsHoldTheImageOfEveryParameterBox) {
  std::mt19937 rng(3);
  for (const Case& c : kCases) {
    const FfdLattice lattice = twistedLattice(c.l, c.m, c.n, c.turns, c.jitter, 5);
    for (int b = 0; b < 40; ++b) {
      Box3 stu{inside({{0, 0, 0}, {1, 1, 1}}, rng), {}};
      for (int k = 0; k < 3; ++k)
        stu.hi[k] = stu.lo[k] + (1 - stu.lo[k]) * std::pow(double(rng() % 1000) / 1000, 2);
      if (b % 4 == 0) stu.hi[b % 3] = stu.lo[b % 3];  // a flat box: a face's image
      const Box3 image = lattice.imageBounds(stu);
      for (int n = 0; n < 50; ++n) {
        const Vec3 x = lattice.forward(inside(stu, rng));
        ASSERT_TRUE(holds(image, x)) << "a point of the image outside its bounds";
      }
    }
  }
}

TEST(FfdMap, TheFastInverseFindsEveryPointAndNothingOutside) {
  std::mt19937 rng(9);
  for (const Case& c : kCases) {
    const FfdMap map(twistedLattice(c.l, c.m, c.n, c.turns, c.jitter, 5));
    ASSERT_FALSE(map.lattice().findFold().has_value());
    double worst = 0;
    for (int n = 0; n < 400; ++n) {
      const Vec3 s = inside({{0, 0, 0}, {1, 1, 1}}, rng), y = map.lattice().forward(s);
      const auto back = map.inverse(y);
      ASSERT_TRUE(back.has_value());
      worst = std::max(worst, distance(*back, s));
      // Any leaf list holding the leaves around y gives the same answer, bit for bit.
      const std::vector<int> near = map.leavesMeeting(
          {{y[0] - 0.01, y[1] - 0.01, y[2] - 0.01}, {y[0] + 0.01, y[1] + 0.01, y[2] + 0.01}});
      const auto again = map.inverse(y, &near);
      ASSERT_TRUE(again.has_value());
      for (int k = 0; k < 3; ++k) ASSERT_TRUE(same((*again)[k], (*back)[k]));
    }
    EXPECT_LT(worst, 1e-9);
    // Beyond the deformed lattice: pushed out along the outward normal of a face.
    for (int n = 0; n < 200; ++n) {
      Vec3 s = inside({{0, 0, 0}, {1, 1, 1}}, rng);
      const int axis = n % 3;
      s[axis] = (n / 3) % 2 ? 1.0 : 0.0;
      Mat3 j;
      const Vec3 y = map.lattice().forward(s, &j);
      // the face's normal: the cross product of the other two columns, facing away from the inside
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      Vec3 normal{j[1][a] * j[2][b] - j[2][a] * j[1][b], j[2][a] * j[0][b] - j[0][a] * j[2][b],
                  j[0][a] * j[1][b] - j[1][a] * j[0][b]};
      double along = 0, len = 0;
      for (int k = 0; k < 3; ++k) along += normal[k] * j[k][axis], len += normal[k] * normal[k];
      const double sign = (along > 0) == (s[axis] == 1.0) ? 1.0 : -1.0;
      len = std::sqrt(len);
      const Vec3 out{y[0] + sign * 0.02 * normal[0] / len, y[1] + sign * 0.02 * normal[1] / len,
                     y[2] + sign * 0.02 * normal[2] / len};
      EXPECT_FALSE(map.inverse(out).has_value());
    }
    EXPECT_FALSE(map.inverse({50, 50, 50}).has_value());
  }
}

TEST(FfdMap, BoxCoversAreSound) {
  std::mt19937 rng(17);
  int inside = 0, outside = 0, partly = 0;
  for (const Case& c : kCases) {
    const FfdMap map(twistedLattice(c.l, c.m, c.n, c.turns, c.jitter, 5));
    const Box3 around{{-2, -2, -0.5}, {2, 2, 2.5}};
    for (int b = 0; b < 300; ++b) {
      const Vec3 lo = frep::inside(around, rng);
      const double size = 0.02 + 0.4 * double(rng() % 1000) / 1000;
      const Box3 box{lo, {lo[0] + size, lo[1] + size, lo[2] + size}};
      const FfdMap::BoxCover cover = map.cover(box);
      inside += cover.cover == FfdMap::Cover::Inside;
      outside += cover.cover == FfdMap::Cover::Outside;
      partly += cover.cover == FfdMap::Cover::Partly;
      for (int n = 0; n < 30; ++n) {
        const auto s = map.inverse(frep::inside(box, rng));
        if (cover.cover == FfdMap::Cover::Inside) {
          ASSERT_TRUE(s.has_value());
        }
        if (cover.cover == FfdMap::Cover::Outside) {
          ASSERT_FALSE(s.has_value());
        }
        if (s) {
          ASSERT_TRUE(holds(cover.preimage, *s));
        }
      }
    }
  }
  // every kind of box came up
  EXPECT_GT(inside, 20);
  EXPECT_GT(outside, 20);
  EXPECT_GT(partly, 20);
}

NodePtr ffd(const FfdLattice& lattice, NodePtr input) {
  return makeNode("ffd", testing::ffdParams(lattice), {std::move(input)}, "ffd");
}

TEST(FfdNode, TheUndeformedLatticeIsTheIdentity) {
  std::mt19937 rng(2);
  const NodePtr input = sphere(0.4, {0.1, 0, 1});
  const Program plain = compile(input);
  const FfdLattice rest(kLatticeRest, 3, 2, 4);
  // The node: the input itself, bit for bit (with no points, or the rest points given).
  const Program none = compile(makeNode(
      "ffd", {{"rest_min", vec3Value(rest.rest().lo)}, {"rest_max", vec3Value(rest.rest().hi)}},
      {input}, "ffd"));
  const Program given = compile(ffd(rest, input));
  // The pull-back itself through the undeformed map: the identity to rounding.
  const FfdField field(std::make_shared<Program>(compile(input)), std::make_shared<FfdMap>(rest));
  for (int n = 0; n < 500; ++n) {
    const Vec3 p = inside({{-1.5, -1, -0.5}, {1.5, 1, 2.5}}, rng);
    const double v = plain.eval(p[0], p[1], p[2]);
    ASSERT_TRUE(same(none.eval(p[0], p[1], p[2]), v));
    ASSERT_TRUE(same(given.eval(p[0], p[1], p[2]), v));
    ASSERT_NEAR(field.eval(p[0], p[1], p[2]), v, 1e-12);
  }
}

TEST(FfdNode, TheValueIsTheInputsWhereTheLatticeCameFrom) {
  std::mt19937 rng(4);
  const NodePtr input = sphere(0.45, {0.1, 0, 1});
  const Program plain = compile(input);
  for (const Case& c : kCases) {
    const FfdLattice lattice = twistedLattice(c.l, c.m, c.n, c.turns, c.jitter, 5);
    const Program deformed = compile(ffd(lattice, input));
    for (int n = 0; n < 300; ++n) {
      const Vec3 s = inside({{0, 0, 0}, {1, 1, 1}}, rng), y = lattice.forward(s),
                 q = lattice.restPoint(s);
      ASSERT_NEAR(deformed.eval(y[0], y[1], y[2]), plain.eval(q[0], q[1], q[2]), 1e-9);
    }
    // Far outside both boxes: untouched, bit for bit.
    for (const Vec3& p : {Vec3{5, 0, 1}, Vec3{0, -4, 0}, Vec3{0, 0, 9}})
      EXPECT_TRUE(same(deformed.eval(p[0], p[1], p[2]), plain.eval(p[0], p[1], p[2])));
  }
}

TEST(FfdNode, NoGhostIsLeftWhereTheLatticeMovedAway) {
  // A bar filling most of the rest box; the lattice is pushed 1.5 along +x, so the rest
  // box's left part is left empty: the bar must not appear there.
  const NodePtr bar = makeNode(
      "box", {{"corner", vec3Value({-0.9, -0.4, 0.1})}, {"size", vec3Value({1.8, 0.8, 1.8})}}, {});
  FfdLattice lattice(kLatticeRest, 2, 2, 2);
  for (int i = 0; i <= 2; ++i)
    for (int j = 0; j <= 2; ++j)
      for (int k = 0; k <= 2; ++k) {
        Vec3 p = lattice.point(i, j, k);
        p[0] += 1.5;
        lattice.setPoint(i, j, k, p);
      }
  const Program f = compile(ffd(lattice, bar));
  EXPECT_LT(f.eval(-0.5, 0, 1), 0.0);  // vacated: once inside the bar, now empty
  EXPECT_GT(f.eval(1.0, 0, 1), 0.0);   // the bar, moved
  EXPECT_GT(f.eval(2.3, 0, 1), 0.0);   // beyond the rest box, inside the moved lattice
}

TEST(FfdNode, AFoldedLatticeOrAWrongPointCountIsRefusedWithTheReason) {
  FfdLattice lattice(kLatticeRest, 4, 4, 4);
  for (int j = 0; j <= 4; ++j)
    for (int k = 0; k <= 4; ++k) {
      Vec3 q = lattice.point(2, j, k);
      q[0] += 3.0;
      lattice.setPoint(2, j, k, q);
    }
  try {
    ffd(lattice, sphere(0.3, {0, 0, 1}));
    FAIL() << "a folded lattice was accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("folds over itself in cell ("), std::string::npos)
        << e.what();
  }
  auto params = testing::ffdParams(FfdLattice(kLatticeRest, 2, 2, 2));
  params["points"].numbers.resize(3 * 26);
  try {
    makeNode("ffd", params, {sphere(0.3, {0, 0, 1})}, "bend");
    FAIL() << "26 points for 27 were accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'points' has 26 points; a 2 x 2 x 2 lattice has 27"),
              std::string::npos)
        << e.what();
  }
  params = testing::ffdParams(FfdLattice(kLatticeRest, 2, 2, 2));
  params["rest_max"] = vec3Value({1, -0.5, 2});
  EXPECT_THROW(makeNode("ffd", params, {sphere(0.3, {0, 0, 1})}, "bend"), ModelError);
  params = testing::ffdParams(FfdLattice(kLatticeRest, 2, 2, 2));
  params["divisions_y"] = realValue(65);
  EXPECT_THROW(makeNode("ffd", params, {sphere(0.3, {0, 0, 1})}, "bend"), ModelError);
}

TEST(FfdNode, BoundsHoldTheDeformedSolid) {
  std::mt19937 rng(8);
  const NodePtr input = sphere(0.45, {0.1, 0, 1});
  for (const Case& c : kCases) {
    const FfdLattice lattice = twistedLattice(c.l, c.m, c.n, c.turns, c.jitter, 5);
    const NodePtr node = ffd(lattice, input);
    const Program f = compile(node);
    // From the structure (the image of the input's box), and from the intervals alone.
    const Box3 b = structuralBounds(node);
    ASSERT_TRUE(std::isfinite(b.lo[0]) && std::isfinite(b.hi[2]));
    const SolidBounds searched = findBounds(f);
    ASSERT_TRUE(searched.bounded());

    // points of the deformed solid lie in the box
    int found = 0;
    for (int n = 0; n < 3000; ++n) {
      const Vec3 y = lattice.forward(inside({{0, 0, 0}, {1, 1, 1}}, rng));
      if (f.eval(y[0], y[1], y[2]) >= 0) {
        ++found;
        ASSERT_TRUE(holds(b, y));
        ASSERT_TRUE(holds(searched.box, y));
      }
    }
    EXPECT_GT(found, 20);
  }
}

TEST(MeshFfd, TheUndeformedLatticeLeavesEveryVertexWhereItWas) {
  MeshingOptions o;
  o.bbox = {{-0.5, -0.5, 0.5}, {0.7, 0.5, 1.5}};
  o.resolution = 0.05;
  const TriangleMesh mesh = polygonize(compile(sphere(0.45, {0.1, 0, 1})), o);
  const TriangleMesh same = deformMesh(mesh, FfdLattice(kLatticeRest, 3, 2, 4));
  ASSERT_EQ(same.triangles.size(), mesh.triangles.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    for (int k = 0; k < 3; ++k) {
      ASSERT_NEAR(same.positions[v][k], mesh.positions[v][k], 1e-6);
      ASSERT_NEAR(same.normals[v][k], mesh.normals[v][k], 1e-5);
    }
}

// The acceptance point: a sphere deformed as a function (the ffd node, meshed) and as a mesh
// (meshed, then its vertices pushed forward) are the same solid to within a cell.
TEST(MeshFfd, ADeformedSphereAsAFunctionAndAsAMeshAgreeWithinACell) {
  const NodePtr ball = sphere(0.45, {0.1, 0, 1});
  const double cell = 0.04;
  for (const Case& c : kCases) {
    const FfdLattice lattice = twistedLattice(c.l, c.m, c.n, c.turns, c.jitter, 5);
    MeshingOptions o;
    o.resolution = cell;
    o.bbox = {{-0.5, -0.5, 0.5}, {0.7, 0.5, 1.5}};
    const TriangleMesh pushed = deformMesh(polygonize(compile(ball), o), lattice);
    const Program pulled = compile(ffd(lattice, ball));
    o.bbox = structuralBounds(ffd(lattice, ball));
    const TriangleMesh meshed = polygonize(pulled, o);
    // both printable
    ASSERT_TRUE(checkMesh(pushed).printable());
    ASSERT_TRUE(checkMesh(meshed).printable());
    // Hausdorff distance, both ways, at the vertices: exact distances to the other mesh.
    const auto toPushed = meshField(pushed, MeshFieldMethod::Exact, 0.0, "pushed");
    const auto toMeshed = meshField(meshed, MeshFieldMethod::Exact, 0.0, "meshed");
    double worst = 0;
    for (const Vec3f& p : meshed.positions)
      worst = std::max(worst, std::abs(toPushed->eval(p[0], p[1], p[2])));
    for (const Vec3f& p : pushed.positions)
      worst = std::max(worst, std::abs(toMeshed->eval(p[0], p[1], p[2])));
    EXPECT_LE(worst, cell) << c.l << "x" << c.m << "x" << c.n << " turns " << c.turns;
    EXPECT_GT(worst, 0.0);
  }
}

TEST(MeshFfd, ProgressIsReportedAndCancelStops) {
  MeshingOptions o;
  o.bbox = {{-0.5, -0.5, 0.5}, {0.7, 0.5, 1.5}};
  o.resolution = 0.008;
  const TriangleMesh mesh = polygonize(compile(sphere(0.45, {0.1, 0, 1})), o);
  ASSERT_GT(mesh.positions.size(), std::size_t(40000));
  int calls = 0;
  MeshFfdOptions options;
  options.progress = [&](double) { return ++calls < 2; };
  EXPECT_THROW(deformMesh(mesh, twistedLattice(2, 2, 2, 0.5, 0.1, 1), options), Cancelled);
  EXPECT_EQ(calls, 2);
}

}  // namespace
}  // namespace frep

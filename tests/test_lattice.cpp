// lattice/: the Sederberg-Parry lattice's forward map, Jacobian, inverse and fold detection,
// and a lattice fitted to follow a surface.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "base/errors.h"
#include "lattice/ffd_lattice.h"
#include "lattice/surface_lattice.h"
#include "lattice_samples.h"

namespace frep {
namespace {

const Box3 kRest{{-1.0, -0.5, 0.0}, {1.0, 0.5, 2.0}};

Vec3 randomLocal(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return {u(rng), u(rng), u(rng)};
}

double distance(const Vec3& a, const Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

TEST(Lattice, TheUndeformedLatticeIsTheIdentityUpTo64Divisions) {
  std::mt19937 rng(1);
  for (const auto& d : {std::array<int, 3>{1, 1, 1}, {3, 4, 5}, {64, 2, 64}}) {
    const FfdLattice lattice(kRest, d[0], d[1], d[2]);
    EXPECT_EQ(lattice.pointCount(), std::size_t(d[0] + 1) * (d[1] + 1) * (d[2] + 1));
    for (int n = 0; n < 200; ++n) {
      const Vec3 s = randomLocal(rng), x = lattice.restPoint(s);
      EXPECT_LT(distance(lattice.deform(x), x), 1e-12);
      const auto back = lattice.inverse(x);
      ASSERT_TRUE(back.has_value());
      EXPECT_LT(distance(*back, s), 1e-12);
    }
    const Vec3 outside{5, 5, 5};
    EXPECT_EQ(lattice.deform(outside)[0], 5.0);  // outside the rest box: untouched
    EXPECT_FALSE(lattice.inverse(outside).has_value());
  }
}

FfdLattice deformed(int l, int m, int n, double turns, double jitter, unsigned seed) {
  return testing::twistedLattice(l, m, n, turns, jitter, seed, kRest);
}

TEST(Lattice, InverseOfForwardIsTheIdentityInMildAndStrongDeformations) {
  std::mt19937 rng(7);
  struct Case {
    int l, m, n;
    double turns, jitter;
  };
  for (const Case c : {Case{4, 3, 5, 0.2, 0.1}, Case{6, 6, 6, 1.6, 0.25}, Case{2, 2, 8, 2.5, 0.2},
                       Case{16, 4, 16, 1.2, 0.3}}) {
    const FfdLattice lattice = deformed(c.l, c.m, c.n, c.turns, c.jitter, 11);
    ASSERT_FALSE(lattice.findFold().has_value()) << "the test lattice itself folds";
    double worst = 0;
    for (int n = 0; n < 500; ++n) {
      const Vec3 s = randomLocal(rng);
      const auto back = lattice.inverse(lattice.forward(s));
      ASSERT_TRUE(back.has_value()) << "no inverse at " << s[0] << " " << s[1] << " " << s[2];
      worst = std::max(worst, distance(*back, s));
    }
    EXPECT_LT(worst, 1e-9) << c.l << "x" << c.m << "x" << c.n << " turns " << c.turns;
  }
}

TEST(Lattice, TheJacobianIsTheDerivativeOfTheForwardMap) {
  const FfdLattice lattice = deformed(5, 4, 6, 1.0, 0.2, 3);
  std::mt19937 rng(5);
  for (int n = 0; n < 50; ++n) {
    const Vec3 s = randomLocal(rng);
    Mat3 j;
    lattice.forward(s, &j);
    for (int c = 0; c < 3; ++c) {
      const double h = 1e-6;
      Vec3 a = s, b = s;
      a[c] -= h;
      b[c] += h;
      const Vec3 fa = lattice.forward(a), fb = lattice.forward(b);
      for (int r = 0; r < 3; ++r) EXPECT_NEAR(j[r][c], (fb[r] - fa[r]) / (2 * h), 1e-6);
    }
  }
}

TEST(Lattice, AFoldIsFoundAndNamesItsCell) {
  FfdLattice lattice(kRest, 4, 4, 4);
  EXPECT_FALSE(lattice.findFold().has_value());
  // One control point moved a little: still no fold.
  Vec3 p = lattice.point(2, 2, 2);
  p[0] += 0.3;
  lattice.setPoint(2, 2, 2, p);
  EXPECT_FALSE(lattice.findFold().has_value());
  // The middle plane of control points pulled far past the next one along x: dX/ds turns
  // negative beyond the middle, where the map turns inside out.
  for (int j = 0; j <= 4; ++j)
    for (int k = 0; k <= 4; ++k) {
      Vec3 q = FfdLattice(kRest, 4, 4, 4).point(2, j, k);
      q[0] += 3.0;
      lattice.setPoint(2, j, k, q);
    }
  const auto fold = lattice.findFold();
  ASSERT_TRUE(fold.has_value());
  EXPECT_GE(fold->cell[0], 2);  // s beyond the middle
  EXPECT_GT(fold->stu[0], 0.5);
  EXPECT_NE(fold->text().find("folds over itself in cell ("), std::string::npos) << fold->text();
}

TEST(Lattice, BadParametersAreRefusedWithWhatIsAllowed) {
  try {
    FfdLattice(kRest, 0, 2, 2);
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("divisions x = 0 is out of range; allowed: 1 to 64"),
              std::string::npos) << e.what();
  }
  EXPECT_THROW(FfdLattice(kRest, 2, 65, 2), ModelError);
  EXPECT_THROW(FfdLattice(Box3{{0, 0, 0}, {1, 0, 1}}, 2, 2, 2), ModelError);
  FfdLattice lattice(kRest, 2, 2, 2);
  EXPECT_THROW(lattice.setPoint(3, 0, 0, {0, 0, 0}), ModelError);
  EXPECT_THROW(lattice.setPoint(0, 0, 0, {NAN, 0, 0}), ModelError);
}

// A lattice fitted to a surface: a plane exactly (Bernstein volumes reproduce linear maps), a
// quarter of a cylinder (radius 20, 30 high, a shell 2 thick) within a hundredth of the
// thickness at random points of the shell, checked against the cylinder itself; bad input
// named.
TEST(SurfaceLattice, FollowsAPlaneExactlyAndACylinderPatchClosely) {
  const Vec3 du{40, 10, 0}, dv{0, 20, 5};
  Vec3 n{du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2],
         du[0] * dv[1] - du[1] * dv[0]};
  n = vscale(n, 1.0 / vlength(n));
  const SurfaceSampler flat = [&](double s, double t) {
    return SurfaceSample{vadd(vadd({10, 5, 3}, vscale(du, s)), vscale(dv, t)), n};
  };
  const SurfaceLattice p = latticeAlongSurface(flat, {41, 21, 2}, 3, 2);
  EXPECT_LT(p.deviation, 1e-9);
  const double radius = 20, height = 30, thickness = 2, quarter = 0.5 * 3.14159265358979323846;
  auto cylinder = [&](double s, double t) {
    const double a = quarter * s;
    return SurfaceSample{{radius * std::cos(a), radius * std::sin(a), height * t},
                         {std::cos(a), std::sin(a), 0.0}};
  };
  const SurfaceLattice c =
      latticeAlongSurface(cylinder, {radius * quarter, height, thickness}, 6, 2);
  EXPECT_EQ(c.lattice.divisions(0), 6);
  EXPECT_EQ(c.lattice.divisions(2), 1);
  EXPECT_LT(c.deviation, 0.01 * thickness);
  std::mt19937 rng(5);
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 stu = randomLocal(rng);
    const SurfaceSample q = cylinder(stu[0], stu[1]);
    const Vec3 want = vadd(q.point, vscale(q.normal, (stu[2] - 0.5) * thickness));
    worst = std::max(worst, distance(c.lattice.forward(stu), want));
  }
  EXPECT_LT(worst, 0.01 * thickness);
  EXPECT_GT(worst, 0.0);
  // the rest box's corner cells: a lattice cell at the rest box's origin lies on the surface's
  // corner, half the thickness inside
  EXPECT_LT(distance(c.lattice.deform({0, 0, 0}), {radius - 0.5 * thickness, 0, 0}),
            0.01 * thickness);
  auto refused = [&](const SurfaceSampler& s, const Vec3& size, int l, int m, const char* what) {
    try {
      latticeAlongSurface(s, size, l, m);
      ADD_FAILURE() << "no error for " << what;
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  refused(cylinder, {1, 1, 1}, 0, 2, "allowed 1 to 24");
  refused(cylinder, {1, 1, 1}, 2, 25, "allowed 1 to 24");
  refused(cylinder, {1, -1, 1}, 2, 2, "along y is -1;");
  refused(
      [](double, double) {
        return SurfaceSample{{NAN, 0, 0}, {0, 0, 1}};
      },
      {1, 1, 1}, 2, 2, "not finite at parameters (0, 0)");
}

}  // namespace
}  // namespace frep

// Straight struts through an FFD (frep/straight_struts.h, the ffd node's `struts` = straight):
// the field against the distance to every strut of the rest box mapped end to end, each strut
// straight between its ends' images (where the curved struts bow away), a bent beam printable
// and written one beam a strut, a graded radius read before the bend, and what is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "frep/bounds.h"
#include "frep/field_sources.h"
#include "frep/node_helpers.h"
#include "frep/periodic_segments.h"
#include "frep/strut_cells.h"
#include "frep/tree.h"
#include "io/mesh_3mf.h"
#include "lattice/ffd_lattice.h"
#include "lattice_samples.h"
#include "mesh/mesher.h"
#include "pipeline/beam_export.h"
#include "test_nodes.h"
#include "volume/field_sources.h"

namespace frep {
namespace {

NodePtr cells(const std::string& type, Vec3 size, double radius, double nodeRadius = 0.0,
              std::vector<NodePtr> inputs = {}, double blend = 0.0) {
  return makeNode("strut_lattice",
                  {{"cell_type", textValue(type)},
                   {"cell", vec3Value(size)},
                   {"radius", realValue(radius)},
                   {"node_radius", realValue(nodeRadius)},
                   {"blend", realValue(blend)},
                   {"origin", vec3Value({0.05, -0.1, 0.02})}},
                  std::move(inputs));
}

NodePtr straight(const FfdLattice& bend, const NodePtr& input,
                 const std::string& struts = "straight") {
  auto params = testing::ffdParams(bend);
  params["struts"] = textValue(struts);
  return makeNode("ffd", params, {input});
}

double distanceToSegment3(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 e = vsub(b, a), d = vsub(p, a);
  const double l2 = vdot(e, e);
  const double t = l2 > 0 ? std::clamp(vdot(d, e) / l2, 0.0, 1.0) : 0.0;
  return vlength(vsub(d, vscale(e, t)));
}

// Every strut of every cell round the rest box, each cut to it and its ends mapped by the bend
// (no bins, no dedup: Kelvin's shared edges come twice, which changes no minimum).
std::vector<StrutPiece> mappedStruts(const UnitCell& cell, const Vec3& size, const Vec3& origin,
                                     const FfdLattice& bend) {
  const Box3 rest = bend.rest();
  std::vector<StrutPiece> out;
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = int(std::floor((rest.lo[a] - origin[a]) / size[a])) - 1;
    hi[a] = int(std::floor((rest.hi[a] - origin[a]) / size[a])) + 1;
  }
  for (int i = lo[0]; i <= hi[0]; ++i)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int k = lo[2]; k <= hi[2]; ++k)
        for (const UnitStrut& s : cell.struts) {
          auto at = [&](const Vec3& u) {
            return Vec3{origin[0] + (u[0] + i) * size[0], origin[1] + (u[1] + j) * size[1],
                        origin[2] + (u[2] + k) * size[2]};
          };
          StrutPiece piece;
          if (clip(at(s.a), at(s.b), rest.lo, rest.hi, &piece))
            out.push_back({bend.deform(piece.a), bend.deform(piece.b)});
        }
  return out;
}

// The bent beam of the curved struts' test: 4 x 1 x 1 divisions lifted along a parabola.
FfdLattice parabola() {
  return testing::parabolaLattice({{-2.05, -0.55, -0.55}, {2.05, 0.55, 0.55}});
}

// The field is radius minus the distance to the nearest mapped strut within 1e-9 at 10,000
// random points round the bent lattice (the distance capped at a cell's longest side), for four
// unit cells through a twisted, shaken lattice (node spheres on one), and for a foam.
TEST(StraightStruts, TheDistanceToTheMappedStrutsAtTenThousandPoints) {
  const Box3 rest{{-1.0, -0.6, -0.4}, {1.1, 0.7, 1.3}};
  const FfdLattice bend = testing::twistedLattice(3, 2, 3, 0.9, 0.08, 5, rest);
  std::mt19937 rng(3);
  for (const std::string type : {"octet", "kelvin", "diamond", "bcc"}) {
    const Vec3 size{0.4, 0.45, 0.35};
    const double nodeRadius = type == "bcc" ? 0.09 : 0.0;
    const NodePtr model = straight(bend, cells(type, size, 0.04, nodeRadius));
    const Program field = compile(model);
    const std::vector<StrutPiece> struts =
        mappedStruts(unitCell(type), size, {0.05, -0.1, 0.02}, bend);
    ASSERT_GT(struts.size(), 100u) << type;
    std::vector<Vec3> nodes;  // the cells' nodes in the rest box, mapped
    for (int i = -4; i <= 4 && nodeRadius > 0.0; ++i)
      for (int j = -4; j <= 4; ++j)
        for (int k = -4; k <= 5; ++k)
          for (const Vec3& n : unitCell(type).nodes) {
            const Vec3 q{0.05 + (n[0] + i) * size[0], -0.1 + (n[1] + j) * size[1],
                         0.02 + (n[2] + k) * size[2]};
            if (q[0] >= rest.lo[0] && q[0] <= rest.hi[0] && q[1] >= rest.lo[1] &&
                q[1] <= rest.hi[1] && q[2] >= rest.lo[2] && q[2] <= rest.hi[2])
              nodes.push_back(bend.deform(q));
          }
    Box3 around{struts[0].a, struts[0].a};
    for (const StrutPiece& s : struts) around = boxHull(around, boxHull({s.a, s.a}, {s.b, s.b}));
    std::uniform_real_distribution<double> x(around.lo[0] - 0.2, around.hi[0] + 0.2),
        y(around.lo[1] - 0.2, around.hi[1] + 0.2), z(around.lo[2] - 0.2, around.hi[2] + 0.2);
    double worst = 0.0;
    for (int i = 0; i < 10000; ++i) {
      const Vec3 p{x(rng), y(rng), z(rng)};
      double d = HUGE_VAL;
      for (const StrutPiece& s : struts) d = std::min(d, distanceToSegment3(p, s.a, s.b));
      // (exact within a cell's longest side of a strut; beyond, the distance is capped there)
      double expected = 0.04 - std::min(d, 0.45);
      if (nodeRadius > 0.0) {
        double n = HUGE_VAL;
        for (const Vec3& q : nodes) n = std::min(n, vlength(vsub(p, q)));
        expected = std::max(expected, nodeRadius - std::min(n, 0.45));
      }
      worst = std::max(worst, std::abs(field.eval(p[0], p[1], p[2]) - expected));
    }
    EXPECT_LT(worst, 1e-9) << type;
  }
  registerVolumeSources();
  const NodePtr foam = makeNode(
      "voronoi_foam", {{"cell", vec3Value({0.5, 0.5, 0.5})}, {"radius", realValue(0.05)}}, {});
  const auto net = std::dynamic_pointer_cast<const PeriodicSegmentsField>(loadFieldSource(*foam));
  ASSERT_TRUE(net);
  std::vector<StrutPiece> edges;
  StrutPiece piece;
  for (const StrutPiece& s : net->segmentsInBox(rest))
    if (clip(s.a, s.b, rest.lo, rest.hi, &piece))
      edges.push_back({bend.deform(piece.a), bend.deform(piece.b)});
  const Program field = compile(straight(bend, foam));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p = bend.deform({0.05 + u(rng), 0.05 + 0.6 * u(rng), 0.45 + 0.8 * u(rng)});
    double d = HUGE_VAL;
    for (const StrutPiece& s : edges) d = std::min(d, distanceToSegment3(p, s.a, s.b));
    worst = std::max(worst, std::abs(field.eval(p[0], p[1], p[2]) - (0.05 - std::min(d, 0.5))));
  }
  EXPECT_LT(worst, 1e-9) << "foam";
}

// Each strut runs straight from one end's image to the other's: the middle of that chord is on
// the strut's axis (the field is the radius there). Curved, the same struts bow away from their
// chords (the parabola bends a strut along x by up to its sagitta), which the test sees.
TEST(StraightStruts, EachStrutIsStraightBetweenItsEndsImages) {
  const FfdLattice bend = parabola();
  const NodePtr octet = cells("octet", {0.5, 0.5, 0.5}, 0.05);
  const Program straightField = compile(straight(bend, octet));
  const Program curvedField = compile(straight(bend, octet, "curved"));
  double worstStraight = 0.0, mostBowed = 0.0;
  int struts = 0;
  for (const StrutPiece& s :
       mappedStruts(unitCell("octet"), {0.5, 0.5, 0.5}, {0.05, -0.1, 0.02}, bend)) {
    if (vlength(vsub(s.b, s.a)) < 0.3) continue;  // (cut short by the rest box)
    const Vec3 m = vscale(vadd(s.a, s.b), 0.5);
    worstStraight = std::max(worstStraight, std::abs(straightField.eval(m[0], m[1], m[2]) - 0.05));
    mostBowed = std::max(mostBowed, 0.05 - curvedField.eval(m[0], m[1], m[2]));
    ++struts;
  }
  EXPECT_GT(struts, 100);
  EXPECT_LT(worstStraight, 1e-9);
  EXPECT_GT(mostBowed, 0.005);  // a curved strut's chord misses its axis by a tenth of the radius
}

// A bent beam of straight octet struts cut to the bent part meshes printable, and as a beam
// 3MF it is one beam a strut (fewer than the curved struts' chains), every beam on a strut's
// axis end to end, the same both ways round; a graded radius is read where the end was before
// the bend, in the field and in the file.
TEST(StraightStruts, ABentBeamMeshesPrintableAndExportsOneBeamAStrut) {
  const FfdLattice bend = parabola();
  const NodePtr part = testing::box({-2, -0.5, -0.5}, {4, 1, 1});
  const NodePtr octet = cells("octet", {0.5, 0.5, 0.5}, 0.05);
  const NodePtr model = straight(bend, makeNode("intersection", {}, {octet, part}));
  MeshingOptions o;
  o.bbox = {{-2.2, -0.7, -0.7}, {2.2, 0.7, 1.8}};
  o.resolution = 0.025;
  EXPECT_TRUE(checkMesh(polygonize(compile(model), o)).printable());

  const std::string path = ::testing::TempDir() + "/straight.3mf";
  const BeamExportResult r =
      exportBeamLattice(model, {o.bbox, 0.05}, MeshSettings(), ThreeMfOptions(), "s", path, false);
  ASSERT_TRUE(r.written);
  const ThreeMfBeams back = read3mfBeams(path);
  ASSERT_EQ(back.beams, r.beams);
  ASSERT_GT(back.beams, 300u);
  const Program field = compile(straight(bend, octet));
  double worst = 0.0;
  for (const auto& e : back.ends)
    for (double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {
      const Vec3 a{e[0][0], e[0][1], e[0][2]}, b{e[1][0], e[1][1], e[1][2]};
      const Vec3 p = vadd(a, vscale(vsub(b, a), t));
      worst = std::max(worst, std::abs(field.eval(p[0], p[1], p[2]) - 0.05));
    }
  EXPECT_LT(worst, 2e-6);  // (the file's coordinates are floats)
  const BeamExportResult curved =
      exportBeamLattice(straight(bend, makeNode("intersection", {}, {octet, part}), "curved"),
                        {o.bbox, 0.05}, MeshSettings(), ThreeMfOptions(), "c", path, false);
  EXPECT_LT(r.beams, curved.beams);
  auto bentPart = testing::ffdParams(bend);
  bentPart["struts"] = textValue("straight");
  const BeamExportResult otherWay = exportBeamLattice(
      makeNode("intersection", {}, {straight(bend, octet), makeNode("ffd", bentPart, {part})}),
      {o.bbox, 0.05}, MeshSettings(), ThreeMfOptions(), "o", path, false);
  EXPECT_EQ(otherWay.beams, r.beams);

  // graded: 0.03 + 0.015 (x + 2), x where the point was (the bend moves points up only)
  const NodePtr radius = makeNode(
      "formula", {{"formula", textValue("0.03 + 0.015 * (x + 2)")}, {"parameters", textValue("")}},
      {});
  const NodePtr graded = straight(
      bend,
      makeNode("intersection", {}, {cells("octet", {0.5, 0.5, 0.5}, 0.05, 0.0, {radius}), part}));
  // on a strut's axis (at its end's image) the field is the radius where that end was
  const Program gradedStruts =
      compile(straight(bend, cells("octet", {0.5, 0.5, 0.5}, 0.05, 0.0, {radius})));
  for (const StrutPiece& s :
       mappedStruts(unitCell("octet"), {0.5, 0.5, 0.5}, {0.05, -0.1, 0.02}, bend)) {
    EXPECT_NEAR(gradedStruts.eval(s.a[0], s.a[1], s.a[2]), 0.03 + 0.015 * (s.a[0] + 2), 1e-9);
  }
  const BeamExportResult g =
      exportBeamLattice(graded, {o.bbox, 0.05}, MeshSettings(), ThreeMfOptions(), "g", path, false);
  ASSERT_TRUE(g.written);
  const ThreeMfBeams gback = read3mfBeams(path);
  ASSERT_EQ(gback.radii.size(), gback.beams);
  for (std::size_t i = 0; i < gback.beams; ++i)
    for (int e = 0; e < 2; ++e)
      EXPECT_NEAR(gback.radii[i][e], 0.03 + 0.015 * (gback.ends[i][e][0] + 2.0), 1e-5);
  std::remove(path.c_str());
}

TEST(StraightStruts, WhatIsRefusedIsNamed) {
  const FfdLattice bend = parabola();
  auto refused = [&](const NodePtr& input, const std::string& expected) {
    try {
      straight(bend, input);
      ADD_FAILURE() << "accepted; expected: " << expected;
    } catch (const ModelError& e) {
      const std::string text = e.what();
      EXPECT_NE(text.find("'struts' = 'straight'"), std::string::npos) << text;
      EXPECT_NE(text.find(expected), std::string::npos) << text;
    }
  };
  refused(makeNode("strut_lattice",
                   {{"conform", textValue("cylinder")}, {"axis", vec3Value({1, 0, 0})}}, {}),
          "'conform' is 'cylinder'");
  refused(makeNode("union", {}, {cells("octet", {0.5, 0.5, 0.5}, 0.05), testing::sphere(1)}),
          "deeper in the input (union)");
  refused(cells("octet", {0.02, 0.02, 0.02}, 0.005), "at most 500000");
  // nothing to straighten: the ffd bends a plain part as it always does
  const Program plain = compile(straight(bend, testing::sphere(0.5)));
  const Program curved = compile(straight(bend, testing::sphere(0.5), "curved"));
  for (double x : {-0.4, 0.0, 0.3}) EXPECT_EQ(plain.eval(x, 0.1, 0.2), curved.eval(x, 0.1, 0.2));
}

// Cells conformal to a cylinder or a sphere with straight struts: the field is radius minus the
// distance to every strut's chord (its ends mapped round the axis), capped at the field's
// exact reach, at 3,000 random points round a slanted axis; the chords' middles are on the
// struts (curved, they are not); a tube and a shell mesh printable and export one beam a
// strut, every beam on a chord.
TEST(StraightStruts, CellsRoundACylinderOrASphereHaveChordsForStruts) {
  const Vec3 origin{0.1, -0.2, 0.3}, axis{0.3, 0.2, 1.0};
  const Frame f = frameAlong(axis);
  for (const bool sphere : {false, true}) {
    const Vec3 size = sphere ? Vec3{0.5, 0.5, 0.5} : Vec3{0.5, 0.6, 0.4};
    const int around = sphere ? 12 : 16;
    auto conformal = [&](const std::string& struts) {
      return makeNode("strut_lattice",
                      {{"cell_type", textValue("octet")},
                       {"cell", vec3Value(size)},
                       {"radius", realValue(0.06)},
                       {"origin", vec3Value(origin)},
                       {"axis", vec3Value(axis)},
                       {"conform", textValue(sphere ? "sphere" : "cylinder")},
                       {"around", realValue(around)},
                       {"struts", textValue(struts)}},
                      {});
    };
    // the map from the lattice's coordinates, written out here
    const double alongY = around / (2 * kPi) * size[1], alongZ = around / (2 * kPi) * size[2];
    auto world = [&](const Vec3& q) {
      const double t = q[1] / alongY, phi = q[2] / alongZ;
      const Vec3 l = sphere ? Vec3{q[0] * std::sin(phi) * std::cos(t),
                                   q[0] * std::sin(phi) * std::sin(t), q[0] * std::cos(phi)}
                            : Vec3{q[0] * std::cos(t), q[0] * std::sin(t), q[2]};
      return vadd(origin, vadd(vscale(f.u, l[0]), vadd(vscale(f.v, l[1]), vscale(f.w, l[2]))));
    };
    // every strut of a turn's cells out to 3.5 from the axis (or centre), each once (by its
    // middle's angle), cut at the axis and the poles
    const double halfTurn = kPi * alongY, pole = kPi * alongZ;
    std::vector<StrutPiece> chords;
    StrutPiece piece;
    for (const StrutPiece& s : strutsInBox(
             unitCell("octet"), size, {0, 0, 0},
             {{0, -halfTurn - 1, sphere ? 0.0 : -2.5}, {3.5, halfTurn + 1, sphere ? pole : 2.5}})) {
      const double middle = 0.5 * (s.a[1] + s.b[1]);
      if (middle < -halfTurn || middle >= halfTurn) continue;
      if (clip(s.a, s.b, {0, -HUGE_VAL, sphere ? 0.0 : -HUGE_VAL},
               {HUGE_VAL, HUGE_VAL, sphere ? pole : HUGE_VAL}, &piece))
        chords.push_back({world(piece.a), world(piece.b)});
    }
    const Program field = compile(conformal("straight"));
    const Program curved = compile(conformal("curved"));
    const double reach = 0.5 * std::min({size[0], size[1], size[2]});
    std::mt19937 rng(sphere ? 9 : 8);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double worst = 0.0;
    for (int i = 0; i < 3000; ++i) {
      Vec3 l{2.5 * u(rng), 2.5 * u(rng), 2.5 * u(rng)};
      // within 2.5 of the axis (and 1.5 along it) or of the centre
      if (std::hypot(l[0], l[1], sphere ? l[2] : 0.0) > 2.5) continue;
      if (!sphere) l[2] *= 0.6;
      const Vec3 p =
          vadd(origin, vadd(vscale(f.u, l[0]), vadd(vscale(f.v, l[1]), vscale(f.w, l[2]))));
      double d = HUGE_VAL;
      for (const StrutPiece& s : chords) d = std::min(d, distanceToSegment3(p, s.a, s.b));
      worst = std::max(worst, std::abs(field.eval(p[0], p[1], p[2]) - (0.06 - std::min(d, reach))));
    }
    EXPECT_LT(worst, 1e-9) << (sphere ? "sphere" : "cylinder");
    double onAxis = 0.0, bowed = 0.0;
    for (const StrutPiece& s : chords) {
      const Vec3 m = vscale(vadd(s.a, s.b), 0.5);
      if (vlength(vsub(m, origin)) > 2.5) continue;
      onAxis = std::max(onAxis, std::abs(field.eval(m[0], m[1], m[2]) - 0.06));
      bowed = std::max(bowed, 0.06 - curved.eval(m[0], m[1], m[2]));
    }
    EXPECT_LT(onAxis, 1e-9);
    EXPECT_GT(bowed, 0.006);  // round the axis a strut's chord misses its curve
    // a tube (a shell) of straight struts meshes printable and is one beam a strut
    const NodePtr part =
        sphere
            ? makeNode("difference", {},
                       {makeNode("sphere",
                                 {{"center", vec3Value(origin)}, {"radius", realValue(2.0)}}, {}),
                        makeNode("sphere",
                                 {{"center", vec3Value(origin)}, {"radius", realValue(1.2)}}, {})})
            : makeNode("difference", {},
                       {makeNode("cylinder",
                                 {{"center", vec3Value(origin)},
                                  {"axis", vec3Value(axis)},
                                  {"radius", realValue(2.0)},
                                  {"length", realValue(1.4)}},
                                 {}),
                        makeNode("cylinder",
                                 {{"center", vec3Value(origin)},
                                  {"axis", vec3Value(axis)},
                                  {"radius", realValue(1.2)},
                                  {"length", realValue(1.8)}},
                                 {})});
    const NodePtr model = makeNode("intersection", {}, {conformal("straight"), part});
    MeshingOptions o;
    o.bbox = {vsub(origin, {2.2, 2.2, 2.2}), vadd(origin, {2.2, 2.2, 2.2})};
    o.resolution = 0.04;
    EXPECT_TRUE(checkMesh(polygonize(compile(model), o)).printable()) << sphere;
    const std::string path = ::testing::TempDir() + "/chords.3mf";
    const BeamExportResult r = exportBeamLattice(model, {o.bbox, 0.06}, MeshSettings(),
                                                 ThreeMfOptions(), "c", path, false);
    ASSERT_TRUE(r.written);
    const ThreeMfBeams back = read3mfBeams(path);
    ASSERT_GT(back.beams, 200u);
    double off = 0.0;
    for (const auto& e : back.ends)
      for (double t : {0.0, 0.5, 1.0}) {
        const Vec3 a{e[0][0], e[0][1], e[0][2]}, b{e[1][0], e[1][1], e[1][2]};
        const Vec3 p = vadd(a, vscale(vsub(b, a), t));
        off = std::max(off, std::abs(field.eval(p[0], p[1], p[2]) - 0.06));
      }
    EXPECT_LT(off, 2e-6) << sphere;
    const BeamExportResult chained =
        exportBeamLattice(makeNode("intersection", {}, {conformal("curved"), part}), {o.bbox, 0.06},
                          MeshSettings(), ThreeMfOptions(), "c", path, false);
    EXPECT_LT(r.beams, chained.beams) << sphere;
    // The lattice alone fills space: the bounds search reaches a million out, where a wedge's
    // cell is long round the axis and thin across, and finds it unbounded (its layers there
    // made in few bins, each of few chords).
    const SolidBounds everywhere = findBounds(field);
    EXPECT_FALSE(everywhere.bounded()) << sphere;
    EXPECT_FALSE(everywhere.empty) << sphere;
    const Vec3 far = vadd(origin, vscale(f.u, 5e5));
    EXPECT_LE(field.eval(far[0], far[1], far[2]), 0.06) << sphere;
    std::remove(path.c_str());
  }
}

}  // namespace
}  // namespace frep

// hsplines through OpenCASCADE: the flattened surface is the hierarchy to 1e-9; a
// closed hspline with detail becomes a valid STEP solid that OpenCASCADE reads back, and its
// mesh is printable by the check.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "hspline/hspline_flatten.h"
#include "hspline/hspline_shapes.h"
#include "hspline/hspline_tessellate.h"
#include "hspline/occt/occ_hspline.h"
#include "io/mesh_io.h"

using namespace frep;

namespace {

HSpline detailedTorus() {
  HSpline h = hsplineTorus(10, 8, 5, 1.5);
  h.refine(0, {{2, 2}, {3, 2}, {7, 5}});
  h.setValue(1, 6, 6, {0.1, 0.2, 0.6});
  h.setValue(1, 7, 6, {0, 0, 0.4});
  h.refine(1, {{7, 6}});
  h.setValue(2, 16, 14, {0, 0, -0.15});
  return h;
}

HSpline detailedPlane() {
  HSpline h = hsplinePlane(9, 8, 10, 9);
  h.moveCv(0, 4, 4, {0, 0, 2});
  h.refine(0, {{4, 4}, {5, 4}});
  h.setValue(1, 8, 8, {0.2, 0, 0.5});
  return h;
}

}  // namespace

TEST(HsOcc, TheOpenCascadeSurfaceIsTheHierarchy) {
  HSpline uneven(SplineAxis::open({0, 0, 0, 0, 0.3, 0.3, 1.1, 2, 2.5, 2.5, 2.5, 2.5}),
                 SplineAxis::periodic({0.5, 0.75, 1.5, 2.0, 2.0, 3.25}, 4.0), [] {
                   std::vector<Vec3> p;
                   for (int j = 0; j < 6; ++j)
                     for (int i = 0; i < 8; ++i)
                       p.push_back({double(i), 3 * std::cos(j * 1.047),
                                    3 * std::sin(j * 1.047) + 0.1 * i * i});
                   return p;
                 }());
  uneven.refine(0, {{3, 2}});
  uneven.setValue(1, 6, 6, {0.1, 0.1, 0.3});
  for (const HSpline& h : {detailedTorus(), detailedPlane(), hsplineCylinder(7, 5, 2, 3), uneven}) {
    const double d = occSurfaceDeviation(h, 40);
    EXPECT_LE(d, 1e-9);
  }
}

TEST(HsOcc, ATorusWithDetailIsAValidStepSolidAndAPrintableStl) {
  const HSpline h = detailedTorus();
  const std::string step = testing::TempDir() + "/torus.step";
  std::remove(step.c_str());
  const OccShapeSummary written = writeHsStep(h, step);
  EXPECT_EQ(written.solids, 1);
  EXPECT_TRUE(written.valid);
  const OccShapeSummary back = readStepSummary(step);
  EXPECT_EQ(back.solids, 1);
  EXPECT_EQ(back.faces, 1);
  EXPECT_TRUE(back.valid);
  EXPECT_NEAR(back.volume, written.volume, 1e-6 * written.volume);
  // Near the plain torus's 2 pi^2 R r^2, detail included.
  EXPECT_NEAR(back.volume, 2 * M_PI * M_PI * 5 * 1.5 * 1.5, 0.05 * 2 * M_PI * M_PI * 5 * 1.5 * 1.5);

  const HsTessellation t = tessellate(flatten(h), 0.002);
  const CheckReport report = checkMesh(t.mesh);
  EXPECT_TRUE(report.printable()) << reportToText(report, "torus");
  EXPECT_TRUE(report.outward);
  // The mesh's volume and OpenCASCADE's agree to the tessellation's accuracy.
  EXPECT_NEAR(report.volume, back.volume, 2e-3 * back.volume);
  const std::string stl = testing::TempDir() + "/torus.stl";
  writeMesh(t.mesh, stl, MeshFormat::StlBinary);
  EXPECT_TRUE(checkMesh(readMesh(stl)).printable());
}

TEST(HsOcc, AnOpenSurfaceIsWrittenAsOneFace) {
  const std::string step = testing::TempDir() + "/plane.step";
  const OccShapeSummary s = writeHsStep(detailedPlane(), step);
  EXPECT_EQ(s.solids, 0);
  EXPECT_EQ(s.faces, 1);
  const OccShapeSummary back = readStepSummary(step);
  EXPECT_EQ(back.faces, 1);
  EXPECT_NEAR(back.area, s.area, 1e-6 * s.area);
  EXPECT_THROW(readStepSummary(step + ".missing"), FileError);
}

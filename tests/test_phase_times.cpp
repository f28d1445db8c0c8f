// The phase recorder the serial-share benchmark reads (base/phase_times.h).
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "base/phase_times.h"
#include "pipeline/export_pipeline.h"
#include "test_nodes.h"

namespace {

using frep::Phase;
using frep::PhaseKind;
using frep::PhaseRecording;
using frep::PhaseTime;

void busy(double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < until) {
  }
}

const PhaseTime* find(const std::vector<PhaseTime>& phases, const std::string& name) {
  for (const PhaseTime& p : phases)
    if (p.name == name) return &p;
  return nullptr;
}

TEST(PhaseTimes, InnerPhasesPauseOuterOnesAndTheSumIsTheWhole) {
  std::vector<PhaseTime> phases;
  const auto start = std::chrono::steady_clock::now();
  {
    PhaseRecording recording;
    {
      const Phase outer("outer", PhaseKind::Parallel);
      busy(0.02);
      {
        const Phase inner("inner", PhaseKind::Serial);
        busy(0.03);
      }
      const Phase again("inner", PhaseKind::Serial);  // summed with the first call
      busy(0.01);
    }
    busy(0.01);  // in no phase
    phases = recording.phases();
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const PhaseTime* outer = find(phases, "outer");
  const PhaseTime* inner = find(phases, "inner");
  const PhaseTime* none = find(phases, "(outside any phase)");
  ASSERT_TRUE(outer && inner && none);
  EXPECT_EQ(outer->kind, PhaseKind::Parallel);
  EXPECT_EQ(inner->kind, PhaseKind::Serial);
  EXPECT_EQ(inner->calls, 2u);
  EXPECT_GE(outer->seconds, 0.02);
  EXPECT_LT(outer->seconds, 0.03);  // the inner phases' 0.04 s are not its own
  EXPECT_GE(inner->seconds, 0.04);
  EXPECT_GE(none->seconds, 0.01);
  double sum = 0.0;
  for (const PhaseTime& p : phases) sum += p.seconds;
  EXPECT_LE(sum, wall);
  EXPECT_GT(sum, 0.07);
}

TEST(PhaseTimes, OtherThreadsAndUnrecordedRunsLeaveNoTrace) {
  {
    const Phase before("before any recording", PhaseKind::Serial);  // nothing listens yet
  }
  PhaseRecording recording;
  std::thread other([] {
    const Phase elsewhere("on another thread", PhaseKind::Serial);
    busy(0.005);
  });
  other.join();
  const std::vector<PhaseTime> phases = recording.phases();
  EXPECT_EQ(find(phases, "before any recording"), nullptr);
  EXPECT_EQ(find(phases, "on another thread"), nullptr);
  EXPECT_THROW(PhaseRecording second, std::logic_error);  // one at a time
}

TEST(PhaseTimes, AnExportIsCutIntoTheMeshersTheChecksAndTheWritersPhases) {
  frep::ExportRequest request;
  request.box.cells = 48;
  const std::string path = ::testing::TempDir() + "phase_times_sphere.stl";
  std::vector<PhaseTime> phases;
  {
    PhaseRecording recording;
    const frep::ExportResult r =
        frep::exportField(frep::compile(frep::testing::sphere(1.0)), request, path, "sphere");
    EXPECT_TRUE(r.written);
    phases = recording.phases();
  }
  for (const char* name : {"mesh: bricks", "mesh: weld", "check: edges and fans",
                           "check: self-intersections", "export: writing"})
    EXPECT_NE(find(phases, name), nullptr) << name;
  EXPECT_EQ(find(phases, "mesh: bricks")->kind, PhaseKind::Parallel);
  EXPECT_EQ(find(phases, "export: writing")->kind, PhaseKind::Serial);
}

}  // namespace

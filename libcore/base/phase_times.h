// Where a run's wall time goes, phase by phase, and which phases run on one thread: what the
// serial-share benchmark (bench/phase_times.cpp) reports to find the serial parts of an
// export. Off unless a PhaseRecording is alive; a phase then costs one relaxed load.
//
// The recording thread's timeline is cut into phases: a phase started inside another pauses
// it, so the phases never overlap and add up to the whole. Time in no phase counts as serial
// (a missed label can only make the share look worse, never better). Phases started on other
// threads are not recorded.
#pragma once

#include <string>
#include <vector>

namespace frep {

enum class PhaseKind {
  Serial,    // one thread does the work
  Parallel,  // the work is spread over TBB's threads
};

struct PhaseTime {
  std::string name;
  PhaseKind kind = PhaseKind::Serial;
  double seconds = 0.0;
  std::size_t calls = 0;
};

// Records the phases of the thread that makes it, while it lives (one at a time).
class PhaseRecording {
 public:
  PhaseRecording();
  ~PhaseRecording();
  PhaseRecording(const PhaseRecording&) = delete;
  PhaseRecording& operator=(const PhaseRecording&) = delete;

  // The phases so far, summed by name in the order they first ran, and the time in no phase
  // as "(outside any phase)", serial.
  std::vector<PhaseTime> phases() const;
};

// Times its scope as the phase `name` (a string literal) when a recording is alive.
class Phase {
 public:
  Phase(const char* name, PhaseKind kind);
  ~Phase();
  Phase(const Phase&) = delete;
  Phase& operator=(const Phase&) = delete;

 private:
  bool recorded_;
};

}  // namespace frep

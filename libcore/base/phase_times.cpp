#include "base/phase_times.h"

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

namespace frep {

namespace {

using Clock = std::chrono::steady_clock;

struct Slot {
  const char* name;
  PhaseKind kind;
};

// The one recording's state; touched by its own thread only, but for `active`.
struct Recorder {
  std::thread::id thread;
  Clock::time_point since;      // when the current slice began
  std::vector<Slot> open;       // the phases entered and not yet left, innermost last
  std::vector<PhaseTime> sums;  // by name, first-seen order; sums[0]: outside any phase

  PhaseTime& sumOf(const Slot& slot) {
    for (PhaseTime& p : sums)
      if (p.name == slot.name && p.kind == slot.kind) return p;
    sums.push_back({slot.name, slot.kind, 0.0, 0});
    return sums.back();
  }
  void closeSlice(Clock::time_point now) {
    const double s = std::chrono::duration<double>(now - since).count();
    since = now;
    (open.empty() ? sums[0] : sumOf(open.back())).seconds += s;
  }
};

std::atomic<Recorder*> active{nullptr};

Recorder* mine() {
  Recorder* r = active.load(std::memory_order_relaxed);
  return r && r->thread == std::this_thread::get_id() ? r : nullptr;
}

}  // namespace

PhaseRecording::PhaseRecording() {
  auto* r = new Recorder;
  r->thread = std::this_thread::get_id();
  r->since = Clock::now();
  r->sums.push_back({"(outside any phase)", PhaseKind::Serial, 0.0, 0});
  Recorder* none = nullptr;
  if (!active.compare_exchange_strong(none, r)) {
    delete r;
    throw std::logic_error("PhaseRecording: one recording at a time");
  }
}

PhaseRecording::~PhaseRecording() {
  delete active.exchange(nullptr);
}

std::vector<PhaseTime> PhaseRecording::phases() const {
  Recorder* r = active.load();
  r->closeSlice(Clock::now());
  return r->sums;
}

Phase::Phase(const char* name, PhaseKind kind) : recorded_(false) {
  Recorder* r = mine();
  if (!r) return;
  recorded_ = true;
  r->closeSlice(Clock::now());
  r->open.push_back({name, kind});
  ++r->sumOf(r->open.back()).calls;
}

Phase::~Phase() {
  if (!recorded_) return;
  Recorder* r = mine();
  if (!r) return;
  r->closeSlice(Clock::now());
  r->open.pop_back();
}

}  // namespace frep

// The one progress type of long work: a range of a caller's progress bar, cut into weighted
// phases or sub-ranges, with the caller's cancel. Every long operation takes a Progress (or
// a plain callback, which becomes one) and hands parts of it to the steps it runs, instead
// of scaling fractions by hand.
#pragma once

#include <atomic>
#include <functional>
#include <initializer_list>
#include <memory>
#include <mutex>
#include <vector>

namespace frep {

// A callback with the fraction done (0..1); false asks the work to stop (Cancelled).
using ProgressCallback = std::function<bool(double)>;

class Progress {
 public:
  // A range that reports nowhere and is never cancelled.
  Progress() = default;
  // The whole bar of `report` (none: as Progress()).
  Progress(ProgressCallback report);  // NOLINT: a callback is a Progress

  // The part [from, from + share) of this range (fractions of it) as a range of its own.
  Progress sub(double from, double share) const;
  // This range cut into consecutive parts in proportion to `weights` (a weight 0 gives an
  // empty part, which reports the point where it stands).
  std::vector<Progress> phases(std::initializer_list<double> weights) const;

  // Reports `fraction` of this range; false when the caller asked to stop.
  bool report(double fraction) const;
  // Reports, and throws Cancelled when the caller asked to stop.
  void step(double fraction) const;
  // `done` of `total` items (total 0: done), as report().
  bool count(std::size_t done, std::size_t total) const;
  // As a plain callback for an API that takes one (empty when this reports nowhere).
  ProgressCallback callback() const;
  // Whether anyone listens: a caller may skip the work of measuring.
  explicit operator bool() const { return static_cast<bool>(report_); }

 private:
  std::shared_ptr<const ProgressCallback> report_;
  double from_ = 0.0, share_ = 1.0;
};

// A range that worker threads report to in `total` items, itemDone() after each: the
// caller's callback is called one call at a time (it need not be thread-safe) and about
// `reports` times in all. Once it says stop, every thread sees cancelled().
class ThreadedProgress {
 public:
  ThreadedProgress(Progress range, std::size_t total, std::size_t reports = 100);
  // One more item done; reports every total / reports items.
  void itemDone();
  bool cancelled() const;

 private:
  Progress range_;
  std::size_t total_, every_;
  std::atomic<std::size_t> done_{0};
  std::atomic<bool> cancelled_{false};
  std::mutex mutex_;  // (held only to report)
};

}  // namespace frep

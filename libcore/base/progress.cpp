#include "base/progress.h"

#include <algorithm>
#include <utility>

#include "base/errors.h"

namespace frep {

Progress::Progress(ProgressCallback report) {
  if (report) report_ = std::make_shared<const ProgressCallback>(std::move(report));
}

Progress Progress::sub(double from, double share) const {
  Progress p = *this;
  p.from_ = from_ + share_ * from;
  p.share_ = share_ * share;
  return p;
}

std::vector<Progress> Progress::phases(std::initializer_list<double> weights) const {
  double total = 0.0;
  for (double w : weights) total += w;
  std::vector<Progress> parts;
  double at = 0.0;
  for (double w : weights) {
    const double share = total > 0.0 ? w / total : 0.0;
    parts.push_back(sub(at, share));
    at += share;
  }
  return parts;
}

bool Progress::report(double fraction) const {
  return !report_ || (*report_)(from_ + share_ * fraction);
}

void Progress::step(double fraction) const {
  if (!report(fraction)) throw Cancelled();
}

bool Progress::count(std::size_t done, std::size_t total) const {
  return report(total == 0 ? 1.0 : static_cast<double>(done) / static_cast<double>(total));
}

ProgressCallback Progress::callback() const {
  if (!report_) return nullptr;
  Progress self = *this;
  return [self](double f) { return self.report(f); };
}

ThreadedProgress::ThreadedProgress(Progress range, std::size_t total, std::size_t reports)
    : range_(std::move(range)),
      total_(total),
      every_(std::max<std::size_t>(1, total / std::max<std::size_t>(1, reports))) {}

void ThreadedProgress::itemDone() {
  const std::size_t done = ++done_;
  if (!range_ || done % every_ != 0) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!range_.count(done, total_)) cancelled_ = true;
}

bool ThreadedProgress::cancelled() const {
  return cancelled_.load(std::memory_order_relaxed);
}

}  // namespace frep

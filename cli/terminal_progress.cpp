#include "cli/terminal_progress.h"

#include <unistd.h>

#include <csignal>
#include <cstdio>

namespace frep::cli {

namespace {
volatile std::sig_atomic_t gInterrupted = 0;
extern "C" void onInterrupt(int) { gInterrupted = 1; }
}  // namespace

void installInterruptHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onInterrupt;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool interrupted() { return gInterrupted != 0; }

TerminalProgress::TerminalProgress(bool enabled)
    : enabled_(enabled), stageStart_(std::chrono::steady_clock::now()) {
  if (!enabled_) return;
  ticker_ = std::thread([this] {
    while (!stop_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
      std::lock_guard<std::mutex> lock(mutex_);
      if (!stop_) draw();
    }
  });
}

TerminalProgress::~TerminalProgress() {
  stop_ = true;
  if (ticker_.joinable()) ticker_.join();
  if (enabled_) std::fprintf(stderr, "\r%60s\r", "");
}

bool TerminalProgress::operator()(ExportStage stage, double fraction) {
  if (enabled_) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stage != stage_) stageStart_ = std::chrono::steady_clock::now();
    stage_ = stage;
    fraction_ = fraction;
    draw();
  }
  return !interrupted();
}

void TerminalProgress::draw() {
  constexpr int kWidth = 24;
  const int filled = static_cast<int>(fraction_ * kWidth + 0.5);
  char bar[kWidth + 1];
  for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
  bar[kWidth] = '\0';
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - stageStart_).count();
  std::fprintf(stderr, "\r%-9s [%s] %3d%% %6.1f s", stageName(stage_), bar,
               static_cast<int>(fraction_ * 100), seconds);
  std::fflush(stderr);
}

}  // namespace frep::cli

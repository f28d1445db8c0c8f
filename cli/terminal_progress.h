// Progress of an export on the terminal, and Ctrl-C.
//
// A bar on stderr across the export's stages (bounds, meshing, checking, writing), redrawn by
// a ticker thread every quarter second so a stage that reports no fractions (CGAL's
// self-intersection test) still shows its elapsed time. Only on a TTY and without --quiet.
// SIGINT and SIGTERM set a flag that the progress callback turns into a cancel: the pipeline
// stops at its next report and the atomic writer removes its temporary file.
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>

#include "base/exit_status.h"
#include "pipeline/export_pipeline.h"

namespace frep::cli {

// Installs the SIGINT/SIGTERM handlers (once); interrupted() tells whether one arrived.
void installInterruptHandlers();
bool interrupted();
// Exit status of a cancelled command (base/exit_status.h).
constexpr int kExitCancelled = static_cast<int>(Outcome::Cancelled);

class TerminalProgress {
 public:
  explicit TerminalProgress(bool enabled);
  ~TerminalProgress();  // clears the line
  TerminalProgress(const TerminalProgress&) = delete;
  TerminalProgress& operator=(const TerminalProgress&) = delete;

  // The pipeline's callback: records the stage and fraction; false once interrupted.
  bool operator()(ExportStage stage, double fraction);

 private:
  void draw();
  bool enabled_;
  std::mutex mutex_;
  ExportStage stage_ = ExportStage::Bounds;
  double fraction_ = 0.0;
  std::chrono::steady_clock::time_point stageStart_;
  std::atomic<bool> stop_{false};
  std::thread ticker_;
};

}  // namespace frep::cli

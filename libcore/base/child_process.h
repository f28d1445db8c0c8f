// Running a helper process with a time limit and a way to stop it: for work that may crash
// the process doing it (a library that trusts a damaged file), done by a child instead.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace frep {

struct ChildResult {
  bool exited = false;  // ended by exit(): exitCode holds its status
  int exitCode = 0;
  int signal = 0;           // the signal that ended it, when it did not exit
  bool timedOut = false;    // killed after `limitSeconds`
  bool cancelled = false;   // killed because `cancelled()` said so
  std::string errorOutput;  // its standard error, the first 4000 bytes
};

// Runs argv[0] (a path, not looked up in PATH) with argv, standard output to /dev/null, and
// waits for it, looking at `cancelled` (may be empty) every few milliseconds. Throws
// std::runtime_error when it cannot be started.
ChildResult runChild(const std::vector<std::string>& argv, double limitSeconds,
                     const std::function<bool()>& cancelled);

}  // namespace frep

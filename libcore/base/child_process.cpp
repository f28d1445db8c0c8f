#include "base/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace frep {

namespace {

// The child's stderr, read as it comes (a line or two) so that the child never blocks on a
// full pipe while the parent waits for it.
class Pipe {
 public:
  Pipe() {
    if (pipe2(fds_, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
    fcntl(fds_[0], F_SETFL, O_NONBLOCK);
  }
  ~Pipe() {
    closeEnd(0);
    closeEnd(1);
  }
  Pipe(const Pipe&) = delete;
  Pipe& operator=(const Pipe&) = delete;
  int writeEnd() const { return fds_[1]; }
  void closeEnd(int k) {
    if (fds_[k] >= 0) close(fds_[k]);
    fds_[k] = -1;
  }
  void drain(std::string& into) {
    char buffer[4096];
    for (;;) {
      const ssize_t n = read(fds_[0], buffer, sizeof buffer);
      if (n <= 0) return;
      if (into.size() < 4000) into.append(buffer, static_cast<std::size_t>(n));
    }
  }

 private:
  int fds_[2] = {-1, -1};
};

}  // namespace

ChildResult runChild(const std::vector<std::string>& argv, double limitSeconds,
                     const std::function<bool()>& cancelled) {
  if (argv.empty()) throw std::invalid_argument("runChild: no program");
  Pipe err;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, err.writeEnd(), STDERR_FILENO);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t child = 0;
  const int spawned = posix_spawn(&child, argv[0].c_str(), &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0)
    throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(spawned));
  err.closeEnd(1);

  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  ChildResult result;
  int status = 0;
  for (;;) {
    err.drain(result.errorOutput);
    const pid_t done = waitpid(child, &status, WNOHANG);
    if (done == child) break;
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    result.cancelled = cancelled && cancelled();
    result.timedOut = !result.cancelled && seconds > limitSeconds;
    if (result.cancelled || result.timedOut) {
      kill(child, SIGKILL);
      waitpid(child, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  err.drain(result.errorOutput);
  result.exited = WIFEXITED(status);
  if (result.exited) result.exitCode = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
  return result;
}

}  // namespace frep

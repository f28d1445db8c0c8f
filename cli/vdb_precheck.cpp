#include "cli/vdb_precheck.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>

#include "base/errors.h"
#include "base/file_names.h"
#include "cli/terminal_progress.h"
#include "volume/grid_set.h"

extern char** environ;

namespace frep::cli {

namespace {

// The child's stderr, read to its end (a line or two) without blocking the wait.
class Pipe {
 public:
  Pipe() {
    if (pipe2(fds_, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
  }
  ~Pipe() {
    closeEnd(0);
    closeEnd(1);
  }
  int readEnd() const { return fds_[0]; }
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

void readVdbInChild(const std::string& path) {
  const std::string name = displayName(path);
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find frepcad's own executable: " + ec.message());
  const auto bytes = std::filesystem::file_size(path, ec);
  const double limit = 30.0 + (ec ? 0.0 : static_cast<double>(bytes) / 20e6);

  Pipe err;
  fcntl(err.readEnd(), F_SETFL, O_NONBLOCK);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, err.writeEnd(), STDERR_FILENO);
  const std::string exe = self.string();
  char* argv[] = {const_cast<char*>(exe.c_str()), const_cast<char*>("__read-vdb"),
                  const_cast<char*>(path.c_str()), nullptr};
  pid_t child = 0;
  const int spawned = posix_spawn(&child, exe.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0)
    throw std::runtime_error(std::string("cannot start the OpenVDB reader: ") +
                             std::strerror(spawned));
  err.closeEnd(1);

  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  std::string said;
  int status = 0;
  for (;;) {
    err.drain(said);
    const pid_t done = waitpid(child, &status, WNOHANG);
    if (done == child) break;
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (interrupted() || seconds > limit) {
      kill(child, SIGKILL);
      waitpid(child, &status, 0);
      if (interrupted()) throw Cancelled();
      throw FileError(name + ": reading the OpenVDB file took over " +
                      std::to_string(static_cast<int>(limit)) + " s: a damaged file?");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  err.drain(said);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  if (WIFSIGNALED(status)) {
    if (interrupted()) throw Cancelled();
    throw FileError(name +
                    ": the OpenVDB file is damaged: OpenVDB's reader crashed on it (signal " +
                    std::to_string(WTERMSIG(status)) + ")");
  }
  // The child's one line, without its "frepcad: ".
  std::string line = said.substr(0, said.find('\n'));
  if (line.rfind("frepcad: ", 0) == 0) line = line.substr(9);
  if (line.empty()) line = name + ": the OpenVDB file could not be read";
  throw FileError(line);
}

int readVdbAlone(const std::string& path) {
  setVdbPrecheck(nullptr);
  readVdb(path);
  return 0;
}

}  // namespace frep::cli

// Work that may crash the process doing it, done by a child (base/child_process.h), and the
// .vdb reader's reading of what its helper did (volume/vdb_reader_child.h).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "base/child_process.h"
#include "base/errors.h"
#include "volume/vdb_reader_child.h"

namespace {

using frep::ChildResult;
using frep::runChild;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A helper program: a shell script standing in for `frepcad __read-vdb PATH` (named for this
// process: tests run side by side).
std::filesystem::path scriptPath(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "-" + std::to_string(getpid()));
}

std::string helperScript(const std::string& name, const std::string& body) {
  const std::filesystem::path path = scriptPath(name);
  std::ofstream(path) << "#!/bin/sh\n" << body << "\n";
  chmod(path.c_str(), 0755);
  return path.string();
}

std::string fileErrorOf(const std::string& helper) {
  try {
    frep::readVdbInHelper(helper, "part.vdb", {});
  } catch (const frep::FileError& e) {
    return e.what();
  }
  return "(no FileError)";
}

TEST(ChildProcess, ItsExitStatusAndErrorOutputComeBack) {
  const ChildResult r =
      runChild({"/bin/sh", "-c", "echo to-stdout; echo oops >&2; exit 3"}, 10, {});
  EXPECT_TRUE(r.exited);
  EXPECT_EQ(r.exitCode, 3);
  EXPECT_EQ(r.errorOutput, "oops\n");  // standard output went to /dev/null
  EXPECT_FALSE(r.timedOut || r.cancelled);
}

TEST(ChildProcess, TheSignalThatEndedItIsReported) {
  const ChildResult r = runChild({"/bin/sh", "-c", "kill -SEGV $$"}, 10, {});
  EXPECT_FALSE(r.exited);
  EXPECT_EQ(r.signal, SIGSEGV);
}

TEST(ChildProcess, OneThatRunsPastItsLimitIsKilled) {
  const auto start = Clock::now();
  const ChildResult r = runChild({"/bin/sleep", "30"}, 0.3, {});
  EXPECT_TRUE(r.timedOut);
  EXPECT_FALSE(r.exited);
  EXPECT_LT(secondsSince(start), 5.0);
}

TEST(ChildProcess, CancelKillsItAtOnce) {
  const auto start = Clock::now();
  const ChildResult r =
      runChild({"/bin/sleep", "30"}, 60, [&] { return secondsSince(start) > 0.2; });
  EXPECT_TRUE(r.cancelled);
  EXPECT_FALSE(r.timedOut);
  EXPECT_LT(secondsSince(start), 5.0);
}

TEST(ChildProcess, AProgramThatCannotStartIsAnError) {
  EXPECT_THROW(runChild({"/no/such/program"}, 10, {}), std::runtime_error);
}

TEST(VdbReaderHelper, ItsOutcomeIsOneLineNamingTheFile) {
  // read: nothing to say
  EXPECT_NO_THROW(frep::readVdbInHelper(helperScript("frep-vdb-ok", "exit 0"), "x.vdb", {}));
  // its own refusal, without its "frepcad: "
  EXPECT_EQ(fileErrorOf(helperScript("frep-vdb-refused",
                                     "echo \"frepcad: part.vdb: not an OpenVDB file\" >&2\n"
                                     "echo second line >&2; exit 2")),
            "part.vdb: not an OpenVDB file");
  // the reader crashed on the file
  EXPECT_EQ(fileErrorOf(helperScript("frep-vdb-crashed", "kill -ABRT $$")),
            "part.vdb: the OpenVDB file is damaged: OpenVDB's reader crashed on it (signal 6)");
  // a helper that says nothing and fails
  EXPECT_EQ(fileErrorOf(helperScript("frep-vdb-silent", "exit 1")),
            "part.vdb: the OpenVDB file could not be read");
  // no helper where one was named
  EXPECT_NE(fileErrorOf("/no/such/frepcad")
                .find("part.vdb: the OpenVDB file could not be read: "
                      "cannot start /no/such/frepcad"),
            std::string::npos);
  // cancelled by the caller
  EXPECT_THROW(frep::readVdbInHelper(helperScript("frep-vdb-slow", "sleep 30"), "x.vdb",
                                     [] { return true; }),
               frep::Cancelled);
  for (const char* name :
       {"frep-vdb-ok", "frep-vdb-refused", "frep-vdb-crashed", "frep-vdb-silent", "frep-vdb-slow"})
    std::filesystem::remove(scriptPath(name));
}

}  // namespace

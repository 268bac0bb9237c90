// Temporaries do not outlive their writer: removed when SIGTERM ends it, and (for SIGKILL, which
// nothing can catch) by the next writer of the same output.
#include "exoid/core/atomic_file.hpp"
#include "exoid/core/temporary_files.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>

namespace exoid::core {
namespace {

namespace fs = std::filesystem;

fs::path freshTemporaryDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("exoid_tmpfiles_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(TemporaryFiles, SigtermRemovesTheGuardedTemporaryAndStillTerminates) {
  const fs::path d = freshTemporaryDir("sigterm");
  const std::string tmp = temporaryPathFor((d / "clip.mp4").string());
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::ofstream(tmp) << "partial";
    const TemporaryFileGuard guard(tmp);
    ::raise(SIGTERM);
    ::_exit(0);  // not reached
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the process must still die of the signal";
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_FALSE(fs::exists(tmp)) << "temporary left behind";
  fs::remove_all(d);
}

TEST(TemporaryFiles, AReleasedGuardLeavesTheFileAlone) {
  const fs::path d = freshTemporaryDir("released");
  const std::string file = (d / "kept").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::ofstream(file) << "renamed into place";
    { const TemporaryFileGuard guard(file); }
    ::raise(SIGTERM);
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(fs::exists(file));
  fs::remove_all(d);
}

TEST(TemporaryFiles, TheNextWriterRemovesTemporariesOfDeadProcessesOnly) {
  const fs::path d = freshTemporaryDir("stale");
  const std::string out = (d / "k.mp4").string();
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);  // reaped: its pid names no process (until reused, which takes long)
  const std::string stale = out + ".tmp." + std::to_string(dead) + ".0";
  const std::string live = out + ".tmp." + std::to_string(::getpid()) + ".99";
  std::ofstream(stale) << "x";
  std::ofstream(live) << "x";
  std::ofstream(d / "other.mp4.tmp.1.0") << "x";  // another output's: not ours to judge
  EXPECT_EQ(removeStaleTemporaries(out), 1);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(d / "other.mp4.tmp.1.0"));
  fs::remove_all(d);
}

}  // namespace
}  // namespace exoid::core

// The one atomic writer: whole files or none, the system's reason in every error, nothing left
// behind, and the pre-flight check's messages.
#include "exoid/core/atomic_file.hpp"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace exoid::core {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("exoid_core_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

int entries(const fs::path& d) {
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(d)) ++n;
  return n;
}

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST(AtomicFile, WritesTheWholeFileAndNothingElse) {
  const fs::path d = freshDir("whole");
  writeFileAtomically((d / "a.txt").string(), std::string_view("hello\n"));
  writeFileAtomically((d / "b.txt").string(), [](std::ostream& o) { o << "x=" << 1.5 << '\n'; });
  EXPECT_EQ(slurp(d / "a.txt"), "hello\n");
  EXPECT_EQ(slurp(d / "b.txt"), "x=1.5\n");
  EXPECT_EQ(entries(d), 2) << "a temporary was left behind";
  fs::remove_all(d);
}

TEST(AtomicFile, AFailedWriteLeavesTheOldFileAndNoTemporary) {
  const fs::path d = freshDir("failed");
  const std::string path = (d / "out.json").string();
  writeFileAtomically(path, std::string_view("old"));
  const std::string msg = messageOf([&] {
    writeFileAtomically(path, [](std::ostream& o) {
      o << "new";
      throw std::runtime_error("the producer failed");
    });
  });
  EXPECT_EQ(msg, "the producer failed");
  EXPECT_EQ(slurp(path), "old");
  EXPECT_EQ(entries(d), 1);
  fs::remove_all(d);
}

// A file-size limit stands in for a full disk: the write fails with the system's reason (EFBIG),
// the target is untouched and the temporary is gone. Run in a child: the limit is per process.
TEST(AtomicFile, AWriteThatHitsTheDiskLimitSaysWhyAndLeavesNothing) {
  const fs::path d = freshDir("limit");
  const std::string path = (d / "big.csv").string();
  int pipefd[2];
  ASSERT_EQ(::pipe(pipefd), 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(pipefd[0]);
    std::signal(SIGXFSZ, SIG_IGN);  // else the limit kills instead of failing the write
    const rlimit lim{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &lim);
    const std::string msg = messageOf([&] { writeFileAtomically(path, std::string(1 << 20, 'x')); });
    [[maybe_unused]] const ssize_t n = ::write(pipefd[1], msg.data(), msg.size());
    ::_exit(0);
  }
  ::close(pipefd[1]);
  std::string msg;
  char buf[512];
  for (ssize_t n; (n = ::read(pipefd[0], buf, sizeof buf)) > 0;) msg.append(buf, static_cast<std::size_t>(n));
  ::close(pipefd[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_NE(msg.find("cannot write '" + path + "': File too large"), std::string::npos) << msg;
  EXPECT_EQ(entries(d), 0) << "the target or a temporary was left behind";
  fs::remove_all(d);
}

TEST(AtomicFile, CheckOutputWritableSaysWhatIsWrongBeforeAnyWork) {
  const fs::path d = freshDir("check");
  EXPECT_NO_THROW(checkOutputWritable((d / "ok.json").string()));
  EXPECT_EQ(entries(d), 0) << "the probe file was left behind";
  EXPECT_NE(messageOf([&] { checkOutputWritable((d / "no" / "x.json").string()); }).find("folder '" + (d / "no").string() + "' does not exist"),
            std::string::npos);
  EXPECT_NE(messageOf([&] { checkOutputWritable(d.string()); }).find("it is a folder"), std::string::npos);
  std::ofstream((d / "file").string()) << "x";
  EXPECT_NE(messageOf([&] { checkOutputWritable((d / "file" / "x.json").string()); }).find("is not a folder"), std::string::npos);
  EXPECT_NE(messageOf([&] { checkOutputWritable("/proc/exoid.json"); }).find("cannot create a file in '/proc'"), std::string::npos);
  fs::remove_all(d);
}

TEST(AtomicFile, PrepareOutputFolderMakesItOrSaysWhyNot) {
  const fs::path d = freshDir("prepare");
  EXPECT_NO_THROW(prepareOutputFolder((d / "a" / "b").string()));
  EXPECT_TRUE(fs::is_directory(d / "a" / "b"));
  EXPECT_EQ(entries(d / "a" / "b"), 0) << "the probe file was left behind";
  EXPECT_NO_THROW(prepareOutputFolder((d / "a" / "b").string()));  // existing: fine
  std::ofstream((d / "file").string()) << "x";
  const std::string msg = messageOf([&] { prepareOutputFolder((d / "file" / "out").string()); });
  EXPECT_NE(msg.find("cannot use '" + (d / "file" / "out").string() + "' as the output folder: Not a directory"), std::string::npos)
      << msg;
  EXPECT_NE(messageOf([&] { prepareOutputFolder((d / "file").string()); }).find("it is a file"), std::string::npos);
  EXPECT_NE(messageOf([&] { prepareOutputFolder("/proc/exoid-out"); }).find("as the output folder"), std::string::npos);
  fs::remove_all(d);
}

TEST(AtomicFile, TemporariesAreUniquePerCallAndRecognisable) {
  const std::string a = temporaryPathFor("/x/out.mp4"), b = temporaryPathFor("/x/out.mp4");
  EXPECT_NE(a, b);
  EXPECT_EQ(a.rfind("/x/out.mp4.tmp." + std::to_string(::getpid()) + ".", 0), 0u) << a;
}

}  // namespace
}  // namespace exoid::core

#include "exoid/render/video_writer.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/render/mp4_check.hpp"

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <spawn.h>
#include <stdexcept>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace exoid::render {

namespace {

bool isExecutableFile(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(p.c_str(), X_OK) == 0;
}

// Writes all bytes to a pipe without dying of SIGPIPE if the reader is gone: SIGPIPE is blocked
// for this thread during the write and a pending one is consumed (no process-wide handler).
bool writeAll(int fd, const std::uint8_t* p, std::size_t n) {
  sigset_t pipe_set, old_set;
  sigemptyset(&pipe_set);
  sigaddset(&pipe_set, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_set, &old_set);
  bool ok = true;
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      ok = false;
      break;
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  if (!ok && errno == EPIPE) {
    const timespec zero{0, 0};
    while (sigtimedwait(&pipe_set, nullptr, &zero) == SIGPIPE) {
    }
  }
  pthread_sigmask(SIG_SETMASK, &old_set, nullptr);
  return ok;
}

}  // namespace

std::string findExecutable(const std::string& name) {
  if (name.empty()) return {};
  if (name.find('/') != std::string::npos) return isExecutableFile(name) ? name : std::string();
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::string dirs(path);
  std::size_t start = 0;
  while (start <= dirs.size()) {
    std::size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    const std::string dir = end > start ? dirs.substr(start, end - start) : std::string(".");
    const std::string candidate = dir + "/" + name;
    if (isExecutableFile(candidate)) return candidate;
    start = end + 1;
  }
  return {};
}

std::string requireFfmpeg(const std::string& name) {
  std::string path = findExecutable(name);
  if (path.empty()) {
    const char* env = std::getenv("PATH");
    throw std::runtime_error("ffmpeg not found ('" + name + "' is not an executable " +
                             (name.find('/') != std::string::npos ? std::string("file") : "on PATH=" + std::string(env ? env : "<unset>")) +
                             "): install ffmpeg (Debian: apt-get install ffmpeg) or give its path");
  }
  return path;
}

VideoWriter::VideoWriter(const std::string& out_path, int width, int height, double fps, const std::string& ffmpeg)
    : out_path_(out_path), tmp_path_(core::temporaryPathFor(out_path)), width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width % 2 != 0 || height % 2 != 0) {
    throw std::invalid_argument("video size must be positive and even (H.264 yuv420p), got " + core::toText(width) +
                                "x" + core::toText(height));
  }
  if (!std::isfinite(fps) || fps <= 0.0 || fps > 240.0) {
    throw std::invalid_argument("'fps' must be in (0, 240], got " + core::formatNumber(fps, 10));
  }
  ffmpeg_ = requireFfmpeg(ffmpeg);
  core::checkOutputWritable(out_path_);  // also removes a SIGKILLed writer's temporaries
  tmp_guard_ = std::make_unique<core::TemporaryFileGuard>(tmp_path_);

  char log_template[] = "/tmp/exoid-ffmpeg-XXXXXX";
  log_fd_ = ::mkstemp(log_template);
  if (log_fd_ < 0) throw std::runtime_error(std::string("cannot create a temporary file for ffmpeg's messages: ") + std::strerror(errno));
  ::unlink(log_template);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    ::close(log_fd_);
    throw std::runtime_error(std::string("cannot create a pipe to ffmpeg: ") + std::strerror(errno));
  }
  const std::string size = core::toText(width) + "x" + core::toText(height);
  const std::string rate = core::formatNumber(fps, 10);
  std::vector<std::string> args{ffmpeg_, "-y", "-nostdin", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
                                "-s", size, "-r", rate, "-i", "-", "-pix_fmt", "yuv420p", "-c:v", "libx264",
                                "-preset", "veryfast", "-f", "mp4", tmp_path_};
  // -nostdin only stops ffmpeg reading the terminal for commands; "-i -" still reads the pipe.
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, log_fd_, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, log_fd_, STDERR_FILENO);
  const int rc = ::posix_spawn(&pid_, ffmpeg_.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[0]);
  pipe_fd_ = fds[1];
  if (rc != 0) {
    pid_ = -1;
    abort();
    throw std::runtime_error("cannot start '" + ffmpeg_ + "': " + std::strerror(rc));
  }
}

VideoWriter::~VideoWriter() { abort(); }

void VideoWriter::abort() noexcept {
  if (pipe_fd_ >= 0) {
    ::close(pipe_fd_);
    pipe_fd_ = -1;
  }
  if (pid_ > 0) {
    ::kill(pid_, SIGTERM);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
  }
  if (log_fd_ >= 0) {
    ::close(log_fd_);
    log_fd_ = -1;
  }
  if (!tmp_path_.empty()) ::unlink(tmp_path_.c_str());
}

namespace {

std::string exitText(int status) {
  if (WIFEXITED(status)) return "it exited with code " + core::toText(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return std::string("it was killed by signal ") + core::toText(WTERMSIG(status));
  return "it stopped";
}

// ffmpeg always says why it fails; silence means the program is not ffmpeg (e.g. --ffmpeg /bin/false).
std::string messagesOrHint(const std::string& messages) {
  return messages.empty() ? "it printed nothing: is it ffmpeg? (--ffmpeg PATH, default: ffmpeg on PATH)" : messages;
}

}  // namespace

std::string VideoWriter::ffmpegMessages() const {
  if (log_fd_ < 0) return {};
  std::string text;
  char buf[4096];
  ssize_t n;
  off_t offset = 0;
  while ((n = ::pread(log_fd_, buf, sizeof buf, offset)) > 0 && text.size() < 8192) {
    text.append(buf, static_cast<std::size_t>(n));
    offset += n;
  }
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text;
}

void VideoWriter::write(const Image& frame) {
  if (pipe_fd_ < 0) throw std::logic_error("VideoWriter::write after finish");
  if (frame.width != width_ || frame.height != height_ || frame.rgb.size() != frame.byteCount()) {
    throw std::invalid_argument("VideoWriter::write: expected a " + core::toText(width_) + "x" +
                                core::toText(height_) + " frame, got " + core::toText(frame.width) + "x" +
                                core::toText(frame.height));
  }
  if (!writeAll(pipe_fd_, frame.rgb.data(), frame.rgb.size())) {
    ::close(pipe_fd_);
    pipe_fd_ = -1;
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    const std::string messages = ffmpegMessages();
    abort();
    throw std::runtime_error("'" + ffmpeg_ + "' stopped taking frames for '" + out_path_ + "' (" + exitText(status) + "): " +
                             messagesOrHint(messages));
  }
  ++frames_;
}

void VideoWriter::finish() {
  if (pid_ <= 0) throw std::logic_error("VideoWriter::finish called twice or after a failure");
  ::close(pipe_fd_);
  pipe_fd_ = -1;
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string how = WIFEXITED(status) ? "exit code " + core::toText(WEXITSTATUS(status))
                                              : "signal " + core::toText(WTERMSIG(status));
    const std::string messages = ffmpegMessages();
    abort();
    throw std::runtime_error("'" + ffmpeg_ + "' failed (" + how + ") writing '" + out_path_ + "': " + messagesOrHint(messages));
  }
  // ffmpeg exits 0 on a full disk with a file that has no index (moov): check before keeping it.
  if (const std::string problem = mp4Problem(tmp_path_); !problem.empty()) {
    abort();
    throw std::runtime_error("ffmpeg reported success but '" + out_path_ + "' is not a complete MP4 (" + problem +
                             "); is the disk full?");
  }
  const std::string tmp = tmp_path_;
  tmp_path_.clear();  // commitTemporary renames it or removes it
  core::commitTemporary(tmp, out_path_);
  ::close(log_fd_);
  log_fd_ = -1;
}

}  // namespace exoid::render

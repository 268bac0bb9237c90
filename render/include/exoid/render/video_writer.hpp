#pragma once
// H.264 MP4 through an ffmpeg child process fed raw RGB frames on a pipe.
#include "exoid/core/temporary_files.hpp"
#include "exoid/render/image.hpp"

#include <memory>
#include <string>
#include <sys/types.h>

namespace exoid::render {

/// Full path of an executable: `name` itself if it contains '/', else the first match in the
/// PATH environment variable. Empty if not found or not executable.
std::string findExecutable(const std::string& name);

/// findExecutable(name), or throws std::runtime_error("ffmpeg not found ...: install ffmpeg ...").
std::string requireFfmpeg(const std::string& name = "ffmpeg");

/// Spawns `ffmpeg -y -loglevel error -f rawvideo -pix_fmt rgb24 -s WxH -r FPS -i -
///   -pix_fmt yuv420p -c:v libx264 -preset veryfast -f mp4 <out>.tmp.<pid>.<n>` (veryfast: half the
/// encoding CPU of the default preset, about the same file size for these scenes); finish() checks
/// that the file is a complete MP4 (ffmpeg exits 0 on a full disk) and renames it to `out_path`.
/// Frames are top-down RGB (Image), so no vflip is needed. Destroying an unfinished writer stops
/// ffmpeg and removes the temporary file; so do SIGINT, SIGTERM and SIGHUP, and a temporary left by
/// a SIGKILLed writer is removed by the next writer of the same output.
class VideoWriter {
 public:
  /// Throws std::runtime_error if ffmpeg is not found ("install ffmpeg"), the output cannot be
  /// written, or the process cannot be started; std::invalid_argument for odd or non-positive
  /// sizes (yuv420p needs even width and height) or fps outside (0, 240].
  VideoWriter(const std::string& out_path, int width, int height, double fps,
              const std::string& ffmpeg = "ffmpeg");
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  /// Sends one frame (must be width x height). Throws std::runtime_error with ffmpeg's message
  /// if ffmpeg stopped.
  void write(const Image& frame);
  /// Closes the pipe, waits for ffmpeg, checks its exit status and renames the output.
  /// Throws std::runtime_error with ffmpeg's messages on failure (the temporary file is removed).
  void finish();


 private:
  void abort() noexcept;
  std::string ffmpegMessages() const;

  std::string out_path_, tmp_path_, ffmpeg_;
  std::unique_ptr<core::TemporaryFileGuard> tmp_guard_;  // removes tmp_path_ if a signal ends the process
  int width_, height_;
  int frames_ = 0;
  int pipe_fd_ = -1;
  int log_fd_ = -1;   // ffmpeg's stderr (an unlinked temporary file)
  pid_t pid_ = -1;
};

}  // namespace exoid::render

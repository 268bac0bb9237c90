#pragma once
// Progress of a long batch: a one-line bar with rate and ETA on a terminal, plain periodic lines
// otherwise (logs, Slurm output files). Thread-safe.
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace exoid::experiments {

class Progress {
 public:
  /// `total` items of which `done` are already finished (resume); `unit` e.g. "runs".
  /// `interactive`: bar redrawn in place (default: isatty(stderr)).
  Progress(long total, long done, std::string unit, std::FILE* out = stderr, int interactive = -1);
  /// One more item finished.
  void tick();
  /// Final line.
  void finish();
  /// "1m05s", "12s".
  static std::string duration(double seconds);

 private:
  void print(bool force);
  long total_, done_, start_done_, printed_done_ = -1;
  std::string unit_;
  std::FILE* out_;
  bool tty_;
  std::chrono::steady_clock::time_point start_, last_print_;
  std::mutex mutex_;
};

}  // namespace exoid::experiments

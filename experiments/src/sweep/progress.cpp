#include "exoid/experiments/sweep/progress.hpp"

#include <cmath>
#include <unistd.h>

namespace exoid::experiments {

Progress::Progress(long total, long done, std::string unit, std::FILE* out, int interactive)
    : total_(total), done_(done), start_done_(done), unit_(std::move(unit)), out_(out),
      tty_(interactive < 0 ? ::isatty(::fileno(out)) == 1 : interactive == 1),
      start_(std::chrono::steady_clock::now()), last_print_(start_) {}

std::string Progress::duration(double seconds) {
  if (!std::isfinite(seconds)) return "?";
  const long s = std::lround(seconds);
  char buf[32];
  if (s >= 3600) {
    std::snprintf(buf, sizeof buf, "%ldh%02ldm", s / 3600, (s % 3600) / 60);
  } else if (s >= 60) {
    std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%lds", s);
  }
  return buf;
}

void Progress::tick() {
  std::lock_guard<std::mutex> lock(mutex_);
  ++done_;
  print(false);
}

void Progress::finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  print(true);
  if (tty_) std::fputc('\n', out_);
  std::fflush(out_);
}

void Progress::print(bool force) {
  const auto now = std::chrono::steady_clock::now();
  const double since_print = std::chrono::duration<double>(now - last_print_).count();
  // A bar can redraw often; log lines every 10 s (and at the end) keep files short.
  if (done_ == printed_done_ && !tty_) return;  // the last line already says this
  if (!force && since_print < (tty_ ? 0.2 : 10.0) && done_ != total_) return;
  last_print_ = now;
  printed_done_ = done_;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const long new_done = done_ - start_done_;
  const double rate = elapsed > 0 ? static_cast<double>(new_done) / elapsed : 0.0;  // per second
  const double eta = rate > 0 ? static_cast<double>(total_ - done_) / rate : std::nan("");
  const double frac = total_ > 0 ? static_cast<double>(done_) / static_cast<double>(total_) : 1.0;
  char line[256];
  if (tty_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(frac * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    std::snprintf(line, sizeof line, "\r[%s] %ld/%ld %s %5.1f %%  %.1f %s/min  ETA %s   ", bar.c_str(), done_, total_,
                  unit_.c_str(), 100.0 * frac, 60.0 * rate, unit_.c_str(), duration(eta).c_str());
  } else {
    std::snprintf(line, sizeof line, "progress: %ld/%ld %s (%.1f %%), %.1f %s/min, elapsed %s, ETA %s\n", done_, total_,
                  unit_.c_str(), 100.0 * frac, 60.0 * rate, unit_.c_str(), duration(elapsed).c_str(), duration(eta).c_str());
  }
  std::fputs(line, out_);
  std::fflush(out_);
}

}  // namespace exoid::experiments

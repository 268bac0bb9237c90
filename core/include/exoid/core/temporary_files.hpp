#pragma once
// Temporary output files never outlive the process that wrote them: removed on SIGINT, SIGTERM
// and SIGHUP while registered, and, for SIGKILL (which no process can catch), by the next writer
// of the same output.
#include <string>

namespace exoid::core {

/// While alive, `path` is removed if the process is ended by SIGINT, SIGTERM or SIGHUP (then the
/// signal's default action follows). The handlers are installed on first use. Up to 64 at once;
/// beyond that the guard is a no-op (the stale clean-up still applies).
class TemporaryFileGuard {
 public:
  explicit TemporaryFileGuard(const std::string& path);
  ~TemporaryFileGuard();
  TemporaryFileGuard(const TemporaryFileGuard&) = delete;
  TemporaryFileGuard& operator=(const TemporaryFileGuard&) = delete;

 private:
  int slot_ = -1;
};

/// Removes the temporaries of `path` (temporaryPathFor's "<path>.tmp.<pid>.<n>") whose process
/// no longer exists; returns how many. checkOutputWritable calls it before the work.
int removeStaleTemporaries(const std::string& path);

}  // namespace exoid::core

#pragma once
// An exclusive lock on an output folder (flock on DIR/.lock), so that two exoid processes never
// write one sweep folder at once. The lock file names its holder (pid, host, start time,
// command) for the message the second process gets; the kernel releases the lock when the holder
// exits, however it exits (a stale .lock file is harmless).
#include <string>

namespace exoid::experiments {

class FolderLock {
 public:
  /// Locks `dir` (which must exist) for `what` (e.g. "exoid sweep"). Throws std::runtime_error
  /// naming the holder if another process has it, or the reason if the lock file cannot be made.
  FolderLock(const std::string& dir, const std::string& what);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace exoid::experiments

#pragma once
// Output files are written under a temporary name in the destination folder and renamed on
// success, so a failed or interrupted run never leaves a half-written file at the final path.
#include <string>

namespace exoid::render {

/// "<path>.tmp<pid>": the temporary name used while `path` is being written (same folder, so
/// the final rename is atomic).
std::string temporaryPathFor(const std::string& path);

/// Checks, before any rendering, that `path` can be written: its folder exists, is a folder and
/// accepts a new file (probed by creating and removing the temporary file), and `path` itself
/// is not a folder. Throws std::runtime_error naming the path and the reason.
void checkOutputWritable(const std::string& path);

/// Writes bytes to temporaryPathFor(path), then renames it to `path`. Throws std::runtime_error.
void writeFileAtomic(const std::string& path, const std::string& bytes);

}  // namespace exoid::render

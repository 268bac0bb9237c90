#pragma once
// Output files appear whole or not at all, and stay whole across a power cut: written to a
// temporary beside the target, flushed to disk (fsync), renamed onto the target, and the rename
// made durable (fsync of the folder). The one writer every exoid module uses.
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>

namespace exoid::core {

/// Calls `write` on a stream to a temporary file in the target's folder and, when the stream is
/// good, syncs it and renames it onto `path`. On any failure the temporary is removed and
/// std::runtime_error names the path and the system's reason (e.g. "No space left on device");
/// an existing file at `path` is left untouched.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);
void writeFileAtomically(const std::string& path, std::string_view bytes);

/// The temporary writeFileAtomically uses for `path`: beside it, unique per process and call
/// (threads write distinct files at once), recognisable by ".tmp." for clean-up.
std::string temporaryPathFor(const std::string& path);

/// Renames a finished temporary (written by someone else, e.g. ffmpeg) onto `path` durably:
/// fsync of the file, rename, fsync of the folder. Removes the temporary on failure.
void commitTemporary(const std::string& tmp, const std::string& path);

/// Throws std::runtime_error, before any work, when `path` cannot be written: its folder is
/// missing, is not a folder, or refuses a new file (probed: root ignores permission bits but not
/// read-only mounts), or `path` is a folder. The message says which and why. Also removes the
/// temporaries of `path` that a killed writer left (removeStaleTemporaries).
void checkOutputWritable(const std::string& path);

/// Creates the output folder `dir` (and its parents) if missing and checks that files can be
/// written in it, before any work: throws std::runtime_error "cannot use 'dir' as the output
/// folder: <the system's reason>" naming the part of the path that failed.
void prepareOutputFolder(const std::string& dir);
/// An output file's folder made (prepareOutputFolder) and the file checked writable in it; an
/// empty path is no output and passes.
void prepareOutputFile(const std::string& path);

}  // namespace exoid::core

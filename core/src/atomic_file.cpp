#include "exoid/core/atomic_file.hpp"

#include "exoid/core/temporary_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <filesystem>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace exoid::core {

namespace {

std::string folderOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string reason(int err) { return err != 0 ? std::strerror(err) : "unknown error"; }

// fsync of a file or folder by name; returns errno (0 on success).
int syncPath(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) return errno;
  const int rc = ::fsync(fd) == 0 ? 0 : errno;
  ::close(fd);
  // Some filesystems cannot sync a folder (EINVAL): the rename is then as durable as they allow.
  return rc == EINVAL ? 0 : rc;
}

}  // namespace

std::string temporaryPathFor(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  return path + ".tmp." + std::to_string(static_cast<long>(::getpid())) + "." + std::to_string(counter++);
}

void commitTemporary(const std::string& tmp, const std::string& path) {
  if (const int err = syncPath(tmp, O_RDONLY)) {
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot write '" + path + "': flushing it to disk failed: " + reason(err));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot move the finished '" + path + "' into place: " + reason(err));
  }
  if (const int err = syncPath(folderOf(path), O_RDONLY | O_DIRECTORY)) {
    throw std::runtime_error("wrote '" + path + "' but could not flush its folder to disk: " + reason(err));
  }
}

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string tmp = temporaryPathFor(path);
  const TemporaryFileGuard guard(tmp);
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write '" + path + "': " + reason(errno));
    errno = 0;
    write(out);
    out.flush();
    if (!out) throw std::runtime_error("cannot write '" + path + "': " + reason(errno));
    out.close();
    if (!out) throw std::runtime_error("cannot write '" + path + "': " + reason(errno));
  } catch (...) {
    ::unlink(tmp.c_str());
    throw;
  }
  commitTemporary(tmp, path);
}

void writeFileAtomically(const std::string& path, std::string_view bytes) {
  writeFileAtomically(path, [&](std::ostream& out) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

void checkOutputWritable(const std::string& path) {
  if (path.empty()) throw std::runtime_error("output path is empty");
  const std::string folder = folderOf(path);
  struct stat st {};
  if (::stat(folder.c_str(), &st) != 0) {
    throw std::runtime_error("cannot write '" + path + "': folder '" + folder + "' " +
                             (errno == ENOENT ? std::string("does not exist") : reason(errno)));
  }
  if (!S_ISDIR(st.st_mode)) throw std::runtime_error("cannot write '" + path + "': '" + folder + "' is not a folder");
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
    throw std::runtime_error("cannot write '" + path + "': it is a folder");
  }
  // access(W_OK) says yes to root on read-only folders: probe by creating the temporary file.
  const std::string tmp = temporaryPathFor(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw std::runtime_error("cannot write '" + path + "': cannot create a file in '" + folder + "': " + reason(errno));
  }
  ::close(fd);
  ::unlink(tmp.c_str());
  removeStaleTemporaries(path);  // once per output, before the work: not a folder scan per write
}

void prepareOutputFolder(const std::string& dir) {
  if (dir.empty()) throw std::runtime_error("output folder is empty");
  std::error_code ec;
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec)) {
    throw std::runtime_error("cannot use '" + dir + "' as the output folder: it is a file");
  }
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    // Name the deepest existing part of the path: what the user must fix.
    std::filesystem::path p = std::filesystem::path(dir);
    while (p.has_parent_path() && p != p.parent_path() && !std::filesystem::exists(p)) p = p.parent_path();
    throw std::runtime_error("cannot use '" + dir + "' as the output folder: " + ec.message() +
                             (p.empty() || p == std::filesystem::path(dir) ? std::string() : " (at '" + p.string() + "')"));
  }
  checkOutputWritable((std::filesystem::path(dir) / ".exoid-write-probe").string());
}

void prepareOutputFile(const std::string& path) {
  if (path.empty()) return;
  if (const auto parent = std::filesystem::path(path).parent_path(); !parent.empty()) prepareOutputFolder(parent.string());
  checkOutputWritable(path);
}

}  // namespace exoid::core

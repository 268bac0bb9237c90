#include "exoid/render/output_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>

namespace exoid::render {

namespace {
std::string folderOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}
}  // namespace

std::string temporaryPathFor(const std::string& path) {
  return path + ".tmp" + std::to_string(static_cast<long>(::getpid()));
}

void checkOutputWritable(const std::string& path) {
  if (path.empty()) throw std::runtime_error("output path is empty");
  const std::string folder = folderOf(path);
  struct stat st {};
  if (::stat(folder.c_str(), &st) != 0) {
    throw std::runtime_error("cannot write '" + path + "': folder '" + folder + "' " +
                             (errno == ENOENT ? std::string("does not exist") : std::strerror(errno)));
  }
  if (!S_ISDIR(st.st_mode)) throw std::runtime_error("cannot write '" + path + "': '" + folder + "' is not a folder");
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
    throw std::runtime_error("cannot write '" + path + "': it is a folder");
  }
  // access(W_OK) says yes to root on read-only folders: probe by creating the temporary file.
  const std::string tmp = temporaryPathFor(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw std::runtime_error("cannot write '" + path + "': cannot create a file in '" + folder +
                             "': " + std::strerror(errno));
  }
  ::close(fd);
  ::unlink(tmp.c_str());
}

void writeFileAtomic(const std::string& path, const std::string& bytes) {
  checkOutputWritable(path);
  const std::string tmp = temporaryPathFor(path);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write '" + tmp + "': " + std::strerror(errno));
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed) {
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot write '" + path + "': write failed (disk full?)");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot rename '" + tmp + "' to '" + path + "': " + why);
  }
}

}  // namespace exoid::render

#pragma once
// Shared by the fuzz targets: the input as a file (for readers that take a path), and a trap for
// broken invariants (an exception that is not one of the documented ones is a crash too: libFuzzer
// reports it as an uncaught exception).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace exoid::fuzz {

inline std::string asFile(const std::uint8_t* data, std::size_t size, const char* suffix) {
  static const std::string stem = "/tmp/exoid-fuzz-" + std::to_string(::getpid());
  const std::string path = stem + suffix;  // a target may write several kinds (model_fuzz: .urdf, .xml)
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) __builtin_trap();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) __builtin_trap();
  std::fclose(f);
  return path;
}

#define EXOID_FUZZ_CHECK(cond) \
  do {                         \
    if (!(cond)) __builtin_trap(); \
  } while (0)

}  // namespace exoid::fuzz

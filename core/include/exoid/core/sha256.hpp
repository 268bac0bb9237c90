#pragma once
// SHA-256 (FIPS 180-4) of bytes and of files: what output manifests (complete.json) record, so a
// rerun can tell an output that is intact from one missing or changed by hand.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace exoid::core {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t bytes);
  void update(std::string_view s) { update(s.data(), s.size()); }
  /// The digest as 64 lowercase hex digits; the object is spent afterwards.
  std::string hexDigest();

 private:
  void block(const unsigned char* p);
  std::uint32_t h_[8];
  unsigned char buf_[64];
  std::size_t used_ = 0;
  std::uint64_t length_ = 0;  // bytes
};

std::string sha256Hex(std::string_view bytes);
/// Streams the file; throws std::runtime_error naming it when it cannot be read.
std::string sha256OfFile(const std::string& path);

}  // namespace exoid::core

#include "exoid/render/mp4_check.hpp"

#include "exoid/core/format.hpp"

#include <cstdint>
#include <fstream>
#include <set>

namespace exoid::render {

namespace {

std::uint64_t bigEndian(const unsigned char* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

std::string mp4Problem(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return "cannot be read";
  const std::uint64_t size = static_cast<std::uint64_t>(in.tellg());
  std::set<std::string> seen;
  std::uint64_t at = 0;
  while (at < size) {
    unsigned char head[16];
    if (size - at < 8) return "it ends inside a box header at byte " + core::toText(at);
    in.seekg(static_cast<std::streamoff>(at));
    if (!in.read(reinterpret_cast<char*>(head), 8)) return "read error at byte " + core::toText(at);
    std::uint64_t box = bigEndian(head, 4);
    const std::string type(reinterpret_cast<const char*>(head) + 4, 4);
    if (box == 1) {  // 64-bit size follows the type
      if (size - at < 16 || !in.read(reinterpret_cast<char*>(head + 8), 8)) return "it ends inside a box header";
      box = bigEndian(head + 8, 8);
    } else if (box == 0) {  // the box extends to the end of the file
      box = size - at;
    }
    if (box < 8) return "box '" + type + "' at byte " + core::toText(at) + " has an impossible size";
    if (box > size - at) {
      return "box '" + type + "' at byte " + core::toText(at) + " needs " + core::toText(box) + " bytes, the file has " +
             core::toText(size - at) + " left (truncated)";
    }
    seen.insert(type);
    at += box;
  }
  for (const char* need : {"ftyp", "mdat", "moov"}) {
    if (!seen.count(need)) return std::string("no ") + need + " box" + (std::string(need) == "moov" ? " (the index)" : "");
  }
  return {};
}

}  // namespace exoid::render

// PNG (ISO/IEC 15948): signature, IHDR, one IDAT (zlib stream of filter-0 rows), IEND.
#include "exoid/render/png.hpp"

#include "exoid/core/format.hpp"

#include <zlib.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace exoid::render {

namespace {

void putU32(std::string& out, std::uint32_t v) {
  out.push_back(static_cast<char>((v >> 24) & 0xFF));
  out.push_back(static_cast<char>((v >> 16) & 0xFF));
  out.push_back(static_cast<char>((v >> 8) & 0xFF));
  out.push_back(static_cast<char>(v & 0xFF));
}

void putChunk(std::string& out, const char type[4], const std::string& data) {
  putU32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.append(type, 4);
  out += data;
  const auto* p = reinterpret_cast<const Bytef*>(out.data() + start);
  const uLong crc = crc32(crc32(0L, Z_NULL, 0), p, static_cast<uInt>(out.size() - start));
  putU32(out, static_cast<std::uint32_t>(crc));
}

}  // namespace

std::string encodePng(const Image& image) {
  if (image.width <= 0 || image.height <= 0 || image.rgb.size() != image.byteCount()) {
    throw std::invalid_argument("encodePng: expected a non-empty image with width*height*3 bytes, got " +
                                core::toText(image.width) + "x" + core::toText(image.height) + " with " +
                                core::toText(image.rgb.size()) + " bytes");
  }
  const std::size_t row_bytes = static_cast<std::size_t>(image.width) * 3;
  std::vector<Bytef> raw;
  raw.reserve((row_bytes + 1) * static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) {
    // Filter type 2 (Up): rendered images have long vertical runs, so this compresses well.
    raw.push_back(2);
    const std::uint8_t* row = image.rgb.data() + static_cast<std::size_t>(y) * row_bytes;
    const std::uint8_t* prev = y > 0 ? row - row_bytes : nullptr;
    for (std::size_t i = 0; i < row_bytes; ++i) raw.push_back(static_cast<Bytef>(row[i] - (prev ? prev[i] : 0)));
  }
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<Bytef> packed(packed_size);
  if (compress2(packed.data(), &packed_size, raw.data(), static_cast<uLong>(raw.size()), 9) != Z_OK) {
    throw std::runtime_error("encodePng: zlib compression failed");
  }

  std::string out("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  putU32(ihdr, static_cast<std::uint32_t>(image.width));
  putU32(ihdr, static_cast<std::uint32_t>(image.height));
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, adaptive filters, no interlace
  putChunk(out, "IHDR", ihdr);
  putChunk(out, "IDAT", std::string(reinterpret_cast<const char*>(packed.data()), packed_size));
  putChunk(out, "IEND", std::string());
  return out;
}

}  // namespace exoid::render

// PNG encoder: the bytes decode back to the same pixels (zlib inflate + Up filter undone), the
// chunks carry valid CRCs, and the same image always gives the same bytes.
#include "exoid/render/png.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace exoid::render {
namespace {

std::uint32_t u32(const std::string& s, std::size_t at) {
  return (std::uint32_t(std::uint8_t(s[at])) << 24) | (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
         (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
}

Image testImage(int w, int h) {
  Image im;
  im.width = w;
  im.height = h;
  im.rgb.resize(im.byteCount());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) im.rgb[static_cast<std::size_t>((y * w + x) * 3 + c)] = static_cast<std::uint8_t>(x * 7 + y * 13 + c * 101);
  return im;
}

TEST(Png, DecodesToTheSamePixels) {
  const Image im = testImage(37, 11);
  const std::string png = encodePng(im);
  ASSERT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  std::size_t at = 8;
  std::string idat;
  std::vector<std::string> types;
  while (at < png.size()) {
    const std::uint32_t len = u32(png, at);
    const std::string type = png.substr(at + 4, 4);
    const std::string data = png.substr(at + 8, len);
    const auto* p = reinterpret_cast<const Bytef*>(png.data() + at + 4);
    EXPECT_EQ(u32(png, at + 8 + len), crc32(crc32(0L, Z_NULL, 0), p, len + 4)) << type;
    if (type == "IHDR") {
      EXPECT_EQ(u32(data, 0), 37u);
      EXPECT_EQ(u32(data, 4), 11u);
      EXPECT_EQ(data.substr(8), std::string("\x08\x02\x00\x00\x00", 5));
    }
    if (type == "IDAT") idat += data;
    types.push_back(type);
    at += 12 + len;
  }
  EXPECT_EQ(types, (std::vector<std::string>{"IHDR", "IDAT", "IEND"}));
  const std::size_t row = 37 * 3;
  std::vector<Bytef> raw((row + 1) * 11);
  uLongf raw_size = static_cast<uLongf>(raw.size());
  ASSERT_EQ(uncompress(raw.data(), &raw_size, reinterpret_cast<const Bytef*>(idat.data()), static_cast<uLong>(idat.size())), Z_OK);
  ASSERT_EQ(raw_size, raw.size());
  std::vector<std::uint8_t> pixels(im.byteCount());
  for (std::size_t y = 0; y < 11; ++y) {
    ASSERT_EQ(raw[y * (row + 1)], 2) << "Up filter";
    for (std::size_t i = 0; i < row; ++i) {
      const std::uint8_t up = y > 0 ? pixels[(y - 1) * row + i] : 0;
      pixels[y * row + i] = static_cast<std::uint8_t>(raw[y * (row + 1) + 1 + i] + up);
    }
  }
  EXPECT_EQ(pixels, im.rgb);
}

TEST(Png, SameImageSameBytes) { EXPECT_EQ(encodePng(testImage(64, 48)), encodePng(testImage(64, 48))); }

TEST(Png, RejectsInconsistentImages) {
  Image im = testImage(4, 4);
  im.rgb.pop_back();
  EXPECT_THROW(encodePng(im), std::invalid_argument);
  EXPECT_THROW(encodePng(Image{}), std::invalid_argument);
}

TEST(ImageStats, VarianceAndDifference) {
  Image flat;
  flat.width = 4;
  flat.height = 2;
  flat.rgb.assign(flat.byteCount(), 77);
  EXPECT_EQ(pixelVariance(flat), 0.0);
  Image half = flat;
  for (std::size_t i = 0; i < half.rgb.size(); ++i) half.rgb[i] = i < half.rgb.size() / 2 ? 0 : 200;
  // Two equal halves at 0 and 200: variance (200/2)^2 exactly.
  EXPECT_DOUBLE_EQ(pixelVariance(half), 100.0 * 100.0);
  EXPECT_DOUBLE_EQ(meanAbsDifference(flat, half), (77.0 + 123.0) / 2.0);
  Image other = flat;
  other.width = 2;
  other.height = 4;
  EXPECT_THROW(meanAbsDifference(flat, other), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::render

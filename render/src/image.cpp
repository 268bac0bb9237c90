#include "exoid/render/image.hpp"

#include "exoid/core/format.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace exoid::render {

namespace {
void checkImage(const Image& image, const char* what) {
  if (image.width <= 0 || image.height <= 0 || image.rgb.size() != image.byteCount()) {
    throw std::invalid_argument(std::string(what) + ": expected a non-empty image with width*height*3 = " +
                                core::toText(image.byteCount()) + " bytes, got " + core::toText(image.width) +
                                "x" + core::toText(image.height) + " with " + core::toText(image.rgb.size()));
  }
}
}  // namespace

double pixelVariance(const Image& image) {
  checkImage(image, "pixelVariance");
  // Integer sums are exact (at most 255^2 * 3 * 8192^2 < 2^63).
  unsigned long long sum = 0, sum2 = 0;
  for (std::uint8_t v : image.rgb) {
    sum += v;
    sum2 += static_cast<unsigned long long>(v) * v;
  }
  const double n = static_cast<double>(image.rgb.size());
  const double mean = static_cast<double>(sum) / n;
  return static_cast<double>(sum2) / n - mean * mean;
}

double meanAbsDifference(const Image& a, const Image& b) {
  checkImage(a, "meanAbsDifference");
  checkImage(b, "meanAbsDifference");
  if (a.width != b.width || a.height != b.height) {
    throw std::invalid_argument("meanAbsDifference: sizes differ (" + core::toText(a.width) + "x" +
                                core::toText(a.height) + " vs " + core::toText(b.width) + "x" +
                                core::toText(b.height) + ")");
  }
  unsigned long long sum = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) sum += static_cast<unsigned long long>(std::abs(a.rgb[i] - b.rgb[i]));
  return static_cast<double>(sum) / static_cast<double>(a.rgb.size());
}

}  // namespace exoid::render

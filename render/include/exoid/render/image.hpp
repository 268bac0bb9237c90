#pragma once
// An 8-bit RGB image, rows top to bottom (the order PNG and ffmpeg's rawvideo expect).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace exoid::render {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3 bytes, row 0 = top

  std::size_t byteCount() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3; }
};

/// Variance of all channel values (0..255 scale) over the image: 0 for a uniform image.
/// Throws std::invalid_argument if the image is empty or rgb has the wrong size.
double pixelVariance(const Image& image);

/// Mean absolute difference per channel value between two images of the same size (0..255).
double meanAbsDifference(const Image& a, const Image& b);

}  // namespace exoid::render

#pragma once
// A minimal PNG encoder (8-bit RGB, no interlace, zlib deflate): the same image gives the same
// bytes (no timestamps or other varying chunks).
#include "exoid/render/image.hpp"

#include <string>

namespace exoid::render {

/// The PNG file bytes. Throws std::invalid_argument for an empty or inconsistent image.
std::string encodePng(const Image& image);

}  // namespace exoid::render

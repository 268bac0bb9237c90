#pragma once
// Is an MP4 file complete? ffmpeg can exit 0 having written a truncated file (a full disk), which
// no player opens: no index box (moov), or boxes that run past the end of the file.
#include <string>

namespace exoid::render {

/// Empty when `path` is a complete MP4: its top-level boxes tile the file exactly and include
/// ftyp, mdat and moov. Otherwise what is wrong, e.g. "no moov box (the index)".
std::string mp4Problem(const std::string& path);

}  // namespace exoid::render

// The MP4 writer never keeps a file no player can open, and says what went wrong: an ffmpeg that
// exits 0 on a full disk without writing the index, a program that is not ffmpeg, and the
// container check itself on hand-made boxes.
#include "exoid/render/mp4_check.hpp"
#include "exoid/render/video_writer.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace exoid::render {
namespace {

namespace fs = std::filesystem;

std::string scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("exoid_mp4_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return (d / name).string();
}

std::string box(const std::string& type, const std::string& payload) {
  const std::uint32_t n = static_cast<std::uint32_t>(8 + payload.size());
  std::string b{static_cast<char>(n >> 24), static_cast<char>(n >> 16), static_cast<char>(n >> 8), static_cast<char>(n)};
  return b + type + payload;
}

std::string writeFile(const std::string& name, const std::string& bytes) {
  const std::string p = scratch(name);
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

// Nothing named like the output or its temporaries is left in its folder.
void expectNothingLeft(const std::string& out) {
  const fs::path p(out);
  for (const auto& e : fs::directory_iterator(p.parent_path())) {
    EXPECT_NE(e.path().filename().string().rfind(p.filename().string(), 0), 0u) << "left behind: " << e.path();
  }
}

TEST(Mp4Check, AcceptsCompleteFilesAndNamesWhatIsMissing) {
  const std::string ftyp = box("ftyp", std::string("isom\0\0\2\0", 8)), mdat = box("mdat", std::string(100, 'x')), moov = box("moov", std::string(40, 'm'));
  EXPECT_EQ(mp4Problem(writeFile("ok.mp4", ftyp + mdat + moov)), "");
  EXPECT_EQ(mp4Problem(writeFile("nomoov.mp4", ftyp + mdat)), "no moov box (the index)");
  const std::string cut = ftyp + mdat + moov.substr(0, 20);
  EXPECT_NE(mp4Problem(writeFile("cut.mp4", cut)).find("box 'moov' at byte 124 needs 48 bytes, the file has 20 left (truncated)"),
            std::string::npos)
      << mp4Problem(writeFile("cut.mp4", cut));
  EXPECT_EQ(mp4Problem(scratch("missing.mp4")), "cannot be read");
}

// An "ffmpeg" that takes every frame and exits 0 but writes no index, as ffmpeg does on a full disk.
std::string fakeFfmpegWithoutIndex() {
  const std::string p = scratch("ffmpeg-full-disk.sh");
  std::ofstream(p) << "#!/bin/sh\nfor a in \"$@\"; do out=\"$a\"; done\ncat > /dev/null\n"
                      "printf '\\000\\000\\000\\020ftypisom\\000\\000\\002\\000\\000\\000\\000\\020mdat12345678' > \"$out\"\nexit 0\n";
  ::chmod(p.c_str(), 0755);
  return p;
}

Image grey(int w, int h) {
  Image im;
  im.width = w;
  im.height = h;
  im.rgb.assign(im.byteCount(), 128);
  return im;
}

TEST(VideoWriter, AnFfmpegThatExitsZeroWithoutTheIndexIsAFailureAndLeavesNothing) {
  const std::string out = scratch("fulldisk.mp4");
  VideoWriter w(out, 16, 16, 10.0, fakeFfmpegWithoutIndex());
  for (int i = 0; i < 5; ++i) w.write(grey(16, 16));
  const std::string msg = messageOf([&] { w.finish(); });
  EXPECT_NE(msg.find("ffmpeg reported success but '" + out + "' is not a complete MP4 (no moov box (the index)); is the disk full?"),
            std::string::npos)
      << msg;
  EXPECT_FALSE(fs::exists(out));
  expectNothingLeft(out);
}

TEST(VideoWriter, AProgramThatIsNotFfmpegIsNamedAndQuestioned) {
  const std::string out = scratch("false.mp4");
  const std::string msg = messageOf([&] {
    VideoWriter w(out, 16, 16, 10.0, "/bin/false");
    for (int i = 0; i < 200; ++i) w.write(grey(16, 16));  // the pipe breaks once false has exited
    w.finish();
  });
  EXPECT_NE(msg.find("'/bin/false'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("exited with code 1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("it printed nothing: is it ffmpeg?"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("Resource temporarily unavailable"), std::string::npos) << msg;
  expectNothingLeft(out);
}

}  // namespace
}  // namespace exoid::render

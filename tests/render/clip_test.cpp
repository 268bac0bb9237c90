// End to end: a simulated trajectory rendered offscreen to MP4 and PNG, checked with ffprobe and
// pixel statistics; error cases fail early with clear messages.
#include "exoid/render/clip.hpp"
#include "exoid/render/png.hpp"
#include "exoid/render/video_writer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace exoid::render {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// A fresh folder per process, removed at exit (the path is leaked on purpose: it must outlive
// static destruction for the atexit handler).
const std::string& scratchDir() {
  static const std::string* dir = [] {
    char tmpl[] = "/tmp/exoid-render-test-XXXXXX";
    const char* d = mkdtemp(tmpl);
    if (!d) throw std::runtime_error("mkdtemp failed");
    auto* path = new std::string(d);
    std::atexit([] { std::filesystem::remove_all(*dir); });
    return path;
  }();
  return *dir;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string runCommand(const std::string& cmd) {
  std::string out;
  std::FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[256];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  pclose(p);
  return out;
}

// Trajectory 3 (hip and knee swing at 1 Hz, 30 deg), 2 s at 1 kHz, simulated once for the suite.
const Track& track2s() {
  static const Track t = [] {
    sim::SimConfig cfg;
    cfg.trajectory = 3;
    cfg.duration_s = 2.0;
    return trackFromSimulation(sim::simulate(cfg), "trajectory 3");
  }();
  return t;
}

ClipOptions smallOptions() {
  ClipOptions o;
  o.render.width = 320;
  o.render.height = 240;
  return o;
}

// Sets an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    const char* old = std::getenv(name);
    had_ = old != nullptr;
    if (had_) old_ = old;
    setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (had_) setenv(name_, old_.c_str(), 1);
    else unsetenv(name_);
  }

 private:
  const char* name_;
  bool had_ = false;
  std::string old_;
};

template <class E>
std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "<no exception>";
}

TEST(Clip, TwoSecondsAt30FpsIs60FramesOf2s) {
  if (findExecutable("ffprobe").empty()) GTEST_SKIP() << "ffprobe not installed";
  const std::string out = scratchDir() + "/clip.mp4";
  const ClipSummary s = renderVideo(track2s(), smallOptions(), out);
  EXPECT_EQ(s.frames, 60);
  EXPECT_DOUBLE_EQ(s.clip_duration_s, 2.0);
  const std::string probe = runCommand("ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                                       "stream=nb_read_frames,duration,codec_name,width,height -of csv=p=0 '" + out + "'");
  // codec,width,height,duration,frames
  EXPECT_EQ(probe, "h264,320,240,2.000000,60\n");
  for (const auto& e : std::filesystem::directory_iterator(scratchDir())) {
    EXPECT_EQ(e.path().filename().string().find("clip.mp4.tmp."), std::string::npos) << "temporary left behind: " << e.path();
  }
}

TEST(Clip, FramesAreNotBlankAndChangeWhileTheLegMoves) {
  ClipOptions o = smallOptions();
  o.overlay_enabled = false;  // only the leg can change between frames
  const Track& tr = track2s();
  TrackRenderer source(tr, o);
  ASSERT_EQ(source.frameCount(), 60);
  Image previous = source.frame(0);
  int moving_pairs = 0;
  for (int k = 1; k < source.frameCount(); ++k) {
    const Image& im = source.frame(k);
    // Not blank: a uniform image has variance 0. The rig (about 1/6 of the pixels, >= 100 levels
    // from the black background) alone gives >= (1/6)(5/6) 100^2 ~ 1400: floor 500.
    EXPECT_GT(pixelVariance(im), 500.0) << "frame " << k;
    const std::size_t r0 = tr.rowAt(source.frameTime_s(k - 1)), r1 = tr.rowAt(source.frameTime_s(k));
    const double dq_deg = kRadToDeg * std::max(std::abs(tr.joints[0].q_rad[r1] - tr.joints[0].q_rad[r0]),
                                               std::abs(tr.joints[1].q_rad[r1] - tr.joints[1].q_rad[r0]));
    // 2 deg moves the foot ~3 cm = 2 pixels here (240 px for 1.57 m): many pixels must change.
    if (dq_deg > 2.0) {
      ++moving_pairs;
      EXPECT_GT(meanAbsDifference(previous, im), 0.05) << "frames " << k - 1 << ", " << k << " (dq " << dq_deg << " deg)";
    }
    previous = im;
  }
  // 30 deg at 1 Hz: |dq| per 1/30 s frame exceeds 2 deg for most of the cycle.
  EXPECT_GT(moving_pairs, 30);
}

// The overlay's text has a band of its own across the top: no part of the leg is drawn under it,
// wherever the motion takes the leg (the rig's colours are saturated, the text and band grey).
TEST(Clip, TheOverlaysTextNeverCoversTheLeg) {
  ClipOptions o;  // the default 640 x 480 of reproduce's still and clip
  const Track& tr = track2s();
  TrackRenderer source(tr, o);
  const auto saturation = [](const Image& im, int x, int y) {
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(im.width) + static_cast<std::size_t>(x));
    const int r = im.rgb[i], g = im.rgb[i + 1], b = im.rgb[i + 2];
    return std::max({r, g, b}) - std::min({r, g, b});
  };
  for (int k = 0; k < source.frameCount(); k += 6) {
    const Image& im = source.frame(k);
    // Seven text lines at 23 px: the band's 180 rows hold them; nothing coloured there.
    int coloured_in_band = 0, coloured_below = 0;
    for (int y = 0; y < im.height; ++y) {
      for (int x = 0; x < im.width / 2; ++x) {  // the left half: the leg's side of the frame
        const bool coloured = saturation(im, x, y) > 40;
        (y < 170 ? coloured_in_band : coloured_below) += coloured ? 1 : 0;
      }
    }
    EXPECT_EQ(coloured_in_band, 0) << "frame " << k;
    EXPECT_GT(coloured_below, 500) << "frame " << k << ": the leg must be drawn below the band";
  }
}

// Writes a still for the cross-process test when asked to (skipped in normal runs).
TEST(ClipHelper, WriteStillForOtherProcess) {
  const char* out = std::getenv("EXOID_RENDER_TEST_STILL_OUT");
  if (!out) GTEST_SKIP() << "helper for Clip.StillIsByteIdenticalAcrossRendersAndProcesses";
  renderStill(track2s(), 1.234, smallOptions(), out);
}

TEST(Clip, StillIsByteIdenticalAcrossRendersAndProcesses) {
  const std::string a = scratchDir() + "/a.png", b = scratchDir() + "/b.png", c = scratchDir() + "/c.png";
  renderStill(track2s(), 1.234, smallOptions(), a);
  renderStill(track2s(), 1.234, smallOptions(), b);  // a new renderer in the same process
  const std::string bytes = slurp(a);
  ASSERT_GT(bytes.size(), 1000u);
  EXPECT_EQ(bytes, slurp(b));

  std::string exe(4096, '\0');
  const ssize_t n = readlink("/proc/self/exe", exe.data(), exe.size());
  ASSERT_GT(n, 0);
  exe.resize(static_cast<std::size_t>(n));
  const std::string env_out = "EXOID_RENDER_TEST_STILL_OUT=" + c;
  std::vector<std::string> env_strings{env_out};
  for (char** e = environ; *e; ++e) env_strings.emplace_back(*e);
  std::vector<char*> envp;
  for (std::string& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  std::string filter = "--gtest_filter=ClipHelper.WriteStillForOtherProcess";
  std::vector<char*> argv{exe.data(), filter.data(), nullptr};
  pid_t pid = -1;
  ASSERT_EQ(posix_spawn(&pid, exe.c_str(), nullptr, nullptr, argv.data(), envp.data()), 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_EQ(bytes, slurp(c));
}

TEST(ClipErrors, MissingFfmpegIsReportedBeforeRendering) {
  ScopedEnv path("PATH", "/nonexistent-exoid-bin");
  const std::string out = scratchDir() + "/noffmpeg.mp4";
  const std::string msg = messageOf<std::runtime_error>([&] { renderVideo(track2s(), smallOptions(), out); });
  EXPECT_NE(msg.find("ffmpeg not found"), std::string::npos) << msg;
  EXPECT_NE(msg.find("install ffmpeg"), std::string::npos) << msg;
  EXPECT_FALSE(std::ifstream(out).good());
}

TEST(ClipErrors, UnwritableOutputIsReportedBeforeRendering) {
  std::string msg = messageOf<std::runtime_error>(
      [&] { renderVideo(track2s(), smallOptions(), "/nonexistent-exoid-dir/clip.mp4"); });
  EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
  // A regular file where a folder should be.
  const std::string file = scratchDir() + "/plain";
  std::ofstream(file) << "x";
  msg = messageOf<std::runtime_error>([&] { renderStill(track2s(), 0.5, smallOptions(), file + "/still.png"); });
  EXPECT_NE(msg.find("is not a folder"), std::string::npos) << msg;
  msg = messageOf<std::runtime_error>([&] { renderStill(track2s(), 0.5, smallOptions(), scratchDir()); });
  EXPECT_NE(msg.find("it is a folder"), std::string::npos) << msg;
}

TEST(ClipErrors, BadFrameTimeNamesTheRecord) {
  const std::string out = scratchDir() + "/late.png";
  const std::string msg = messageOf<std::invalid_argument>([&] { renderStill(track2s(), 2.5, smallOptions(), out); });
  EXPECT_NE(msg.find("outside the record [0"), std::string::npos) << msg;
  EXPECT_FALSE(std::ifstream(out).good());
}

TEST(ClipErrors, BadOptions) {
  ClipOptions o = smallOptions();
  o.render.width = 321;  // odd: H.264 yuv420p needs even sizes
  EXPECT_THROW(renderVideo(track2s(), o, scratchDir() + "/odd.mp4"), std::invalid_argument);
  o = smallOptions();
  o.fps = 0;
  EXPECT_THROW(renderVideo(track2s(), o, scratchDir() + "/zero.mp4"), std::invalid_argument);
  o = smallOptions();
  o.render.width = 8;
  EXPECT_THROW(TrackRenderer(track2s(), o), std::invalid_argument);
}

TEST(ClipErrors, ContextThatCannotBeCreatedIsAClearError) {
  ClipOptions o = smallOptions();
  o.render.width = 40000;  // beyond llvmpipe's maximum framebuffer size (16384)
  o.render.height = 16;
  const std::string msg = messageOf<std::runtime_error>([&] { TrackRenderer source(track2s(), o); });
  EXPECT_NE(msg.find("cannot create the"), std::string::npos) << msg;
  // The failed context was released: rendering still works afterwards.
  TrackRenderer ok(track2s(), smallOptions());
  EXPECT_GT(pixelVariance(ok.at(0.5)), 500.0);
}

}  // namespace
}  // namespace exoid::render

// Offscreen rendering cost (OSMesa/llvmpipe): ms per frame at 640x480 with and without shadows
// (scene update + draw + overlay + read-back), and a whole default clip (5 s of trajectory 3 at
// 640x480, 30 fps, H.264 through ffmpeg) as the ratio of wall time to clip duration (< 1 is
// faster than real time). Run: ./render_bench --benchmark_min_time=2
#include "exoid/render/clip.hpp"
#include "exoid/render/video_writer.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <unistd.h>

namespace {

using namespace exoid;

const render::Track& track5s() {
  static const render::Track t = [] {
    sim::SimConfig cfg;
    cfg.trajectory = 3;
    cfg.duration_s = 5.0;
    return render::trackFromSimulation(sim::simulate(cfg), "trajectory 3 (simulated)");
  }();
  return t;
}

void BM_Frame640x480(benchmark::State& state) {
  render::ClipOptions o;
  o.render.shadows = state.range(0) != 0;
  o.render.multisamples = static_cast<int>(state.range(1));
  render::TrackRenderer source(track5s(), o);
  source.frame(0);  // the first frame compiles shaders and uploads textures
  int k = 1;
  for (auto _ : state) {
    benchmark::DoNotOptimize(source.frame(k).rgb.data());
    k = k + 1 < source.frameCount() ? k + 1 : 0;
  }
  state.SetLabel(std::string(o.render.shadows ? "shadows" : "no shadows") +
                 (o.render.multisamples ? ", 4x MSAA" : ""));
}
BENCHMARK(BM_Frame640x480)->Args({0, 0})->Args({1, 0})->Args({0, 4})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_DefaultClipToMp4(benchmark::State& state) {
  if (render::findExecutable("ffmpeg").empty()) {
    state.SkipWithError("ffmpeg not installed");
    return;
  }
  const std::string out = "/tmp/exoid-render-bench-" + std::to_string(static_cast<long>(getpid())) + ".mp4";
  render::ClipSummary s;
  for (auto _ : state) s = render::renderVideo(track5s(), render::ClipOptions{}, out);
  std::remove(out.c_str());
  state.counters["frames"] = s.frames;
  state.counters["ms_per_frame"] = s.ms_per_frame;
  state.counters["render_to_clip_ratio"] = s.realtime_ratio;
}
BENCHMARK(BM_DefaultClipToMp4)->Iterations(3)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

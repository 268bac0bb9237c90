// Long logs (issue 11): a 1,000,000-row dataset CSV (1000 s at 1 kHz, 5 columns written with
// %.17g, ~96 MB), read, processed as `exoid identify` does by default (the band chosen from the
// record, parallel filtering and decimation) and identified by LS and by the exact L1 optimum
// (LAD), end to end.
//
//   build/bench/long_log_bench --benchmark_filter=Ingest
//   build/bench/long_log_bench --benchmark_filter=LsEndToEnd    (one per process: peak_rss_MB is
//   build/bench/long_log_bench --benchmark_filter=LadEndToEnd    the process's high-water mark)
//   build/bench/long_log_bench --benchmark_filter=CliIdentify    (`exoid identify --method ls` as a
//                                                                 user runs it, and the library path
//                                                                 in the same run: their ratio)
//
// Targets: ingest >= 200 MB/s; LS end to end <= 0.5 s with peak memory <= 2.5x the numeric
// payload (1e6 x 5 doubles = 40 MB), through the library and through the CLI; LAD end to end <= 2 s.
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/estimators/lad.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/signals/processing.hpp"
#include "exoid/core/heap.hpp"
#include "exoid/core/random.hpp"

#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

namespace {

constexpr long kRows = 1000000;

// As exoid's main: freed block buffers kept in the heap, the heap on transparent huge pages.
const bool kMallocTuned = [] {
  exoid::core::tuneHeapForLongLogs(true);
  return true;
}();

// Written once per process, streamed (a few kB of memory), removed at exit.
const std::string& bigLog() {
  static const std::string path = [] {
    const std::string p = (std::filesystem::temp_directory_path() / "exoid_long_log_bench.csv").string();
    std::FILE* f = std::fopen(p.c_str(), "w");
    std::fprintf(f, "# thigh_length_m: 0.45\nt,q_hip,q_knee,tau_hip,tau_knee\n");
    exoid::core::Rng rng(1);
    for (long i = 0; i < kRows; ++i) {
      const double t = 1e-3 * static_cast<double>(i);
      const double q1 = -0.5 - 0.5 * std::sin(2 * M_PI * 0.7 * t) + 0.1 * std::sin(2 * M_PI * 1.9 * t);
      const double q2 = 1.2 - 0.5 * std::sin(2 * M_PI * 0.9 * t) + 0.1 * std::cos(2 * M_PI * 2.3 * t);
      std::fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g\n", t, q1, q2, 20 * std::sin(q1) + 3 * std::cos(q2) + 0.5 * rng.uniform(-1.0, 1.0),
                   5 * std::sin(q1 + q2) + 0.5 * rng.uniform(-1.0, 1.0));
    }
    std::fclose(f);
    std::atexit([] { std::filesystem::remove(std::filesystem::temp_directory_path() / "exoid_long_log_bench.csv"); });
    return p;
  }();
  return path;
}

double peakRssMB() {  // 1 MB = 1e6 bytes, as the payload
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) * 1024.0 / 1e6;  // ru_maxrss is in kB on Linux
}

exoid::ident::SignalOptions identifyDefaults() {  // as exoid identify (experiments::defaultIdentifySignals)
  exoid::ident::SignalOptions o;
  o.processing = exoid::ident::Processing::kParallel;
  o.differentiation = exoid::ident::Differentiation::kCentral4;
  o.base_terms = exoid::ident::BaseTerms::kAuto;
  o.cutoff_from_data = true;  // the bands read from the record's spectrum (issue 21's default)
  o.derivative_cutoff_from_data = true;
  return o;
}

void BM_Ingest(benchmark::State& state) {
  const std::string& path = bigLog();
  const auto bytes = static_cast<std::int64_t>(std::filesystem::file_size(path));
  for (auto _ : state) benchmark::DoNotOptimize(exoid::ident::readDatasetCsv(path).size());
  state.SetBytesProcessed(state.iterations() * bytes);
  state.counters["rows"] = static_cast<double>(kRows);
}
BENCHMARK(BM_Ingest)->Unit(benchmark::kMillisecond)->UseRealTime();

template <bool kLad>
void endToEnd(benchmark::State& state) {
  const std::string& path = bigLog();
  const exoid::ident::LegConstants c{0.45, 9.81};
  Eigen::VectorXd x;
  for (auto _ : state) {
    const exoid::ident::RecordRows p = exoid::ident::processRecord(exoid::ident::readDatasetCsv(path), exoid::ident::twoLinkLeg(c), identifyDefaults());
    x = kLad ? exoid::ident::solveLeastAbsoluteDeviations(p.W, p.y).x : exoid::ident::solveLeastSquares(p.W, p.y).x;
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["peak_rss_MB"] = peakRssMB();
  state.counters["payload_MB"] = kRows * 5 * 8 / 1e6;
  state.counters["peak_over_payload"] = peakRssMB() / (kRows * 5 * 8 / 1e6);
}
void BM_LsEndToEnd(benchmark::State& state) { endToEnd<false>(state); }
void BM_LadEndToEnd(benchmark::State& state) { endToEnd<true>(state); }
BENCHMARK(BM_LsEndToEnd)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LadEndToEnd)->Unit(benchmark::kMillisecond)->UseRealTime();

#ifdef EXOID_BINARY
// One `exoid identify` as a user runs it (its own process: start, read, process, fit, report to
// /dev/null); returns the wall time and the child's peak resident memory.
struct ChildRun {
  double wall_s = 0, peak_rss_MB = 0;
};
ChildRun runExoidIdentify(const std::string& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);  // the report, and the warnings a synthetic log earns
    std::freopen("/dev/null", "w", stderr);
    execl(EXOID_BINARY, EXOID_BINARY, "identify", "--data", log.c_str(), "--method", "ls", static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  rusage u{};
  wait4(pid, &status, 0, &u);
  ChildRun r;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.peak_rss_MB = static_cast<double>(u.ru_maxrss) * 1024.0 / 1e6;
  // Exit 3 (a result flagged unusable) still measured the whole run; anything else is a failure.
  if (!WIFEXITED(status) || (WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != 3)) r.wall_s = -1;
  return r;
}

// The CLI against the library path, alternated in one run so both see the same machine.
void BM_CliIdentify(benchmark::State& state) {
  const std::string& path = bigLog();
  const exoid::ident::LegConstants c{0.45, 9.81};
  double cli_s = 0, library_s = 0, peak_MB = 0;
  for (auto _ : state) {
    const ChildRun run = runExoidIdentify(path);
    if (run.wall_s < 0) {
      state.SkipWithError("exoid identify failed");
      return;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const exoid::ident::RecordRows p = exoid::ident::processRecord(exoid::ident::readDatasetCsv(path), exoid::ident::twoLinkLeg(c), identifyDefaults());
    benchmark::DoNotOptimize(exoid::ident::solveLeastSquares(p.W, p.y).x.data());
    library_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    cli_s += run.wall_s;
    peak_MB = std::max(peak_MB, run.peak_rss_MB);
    state.SetIterationTime(run.wall_s);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["cli_s"] = cli_s / n;
  state.counters["library_s"] = library_s / n;
  state.counters["cli_over_library"] = cli_s / library_s;
  state.counters["cli_peak_rss_MB"] = peak_MB;
  state.counters["cli_peak_over_payload"] = peak_MB / (kRows * 5 * 8 / 1e6);
}
BENCHMARK(BM_CliIdentify)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(5);
#endif

}  // namespace

BENCHMARK_MAIN();

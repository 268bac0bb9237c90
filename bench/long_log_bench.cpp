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
//   build/bench/long_log_bench --benchmark_filter=ChainLsEndToEnd
//   build/bench/long_log_bench --benchmark_filter=CliChainAgainstLeg  (a 6-DOF arm's 300,000-row log
//                                                                 from its URDF against the 2-link
//                                                                 leg's 1,000,000 rows, alternated)
//
// Targets: ingest >= 200 MB/s; LS end to end <= 0.5 s with peak memory <= 2.5x the numeric
// payload (1e6 x 5 doubles = 40 MB), through the library and through the CLI; LAD end to end <= 2 s.
// The arm (6 joints, t and q, qd, qdd, tau per joint: 25 columns at %.17g, ~150 MB): through the
// CLI at most 3x the 2-link log's time, with a peak of at most 3x its file's size.
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/estimators/lad.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/signals/processing.hpp"
#include "exoid/core/heap.hpp"
#include "exoid/core/random.hpp"
#include "exoid/ident/model/newton_euler.hpp"
#include "exoid/ident/model/robot.hpp"

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

// A 6-DOF arm (UR5-like geometry and masses), every joint frame unrotated: its URDF and the same
// chain as ident reads it. Each row: the origin in the parent link, the axis, the link's mass, COM
// and principal inertia about it.
struct ArmLink {
  double x, y, z, ax, ay, az, mass, cx, cy, cz, ixx, iyy, izz;
};
constexpr ArmLink kArm[6] = {{0, 0, 0.089159, 0, 0, 1, 3.7, 0, 0, 0, 0.0102, 0.0102, 0.00666},
                             {0, 0.13585, 0, 0, 1, 0, 8.393, 0, 0, 0.28, 0.2269, 0.2269, 0.0151},
                             {0, -0.1197, 0.425, 0, 1, 0, 2.275, 0, 0, 0.25, 0.0494, 0.0494, 0.004095},
                             {0, 0, 0.39225, 0, 1, 0, 1.219, 0, 0.093, 0, 0.0111, 0.0111, 0.0219},
                             {0, 0.093, 0, 0, 0, 1, 1.219, 0, 0, 0.09465, 0.0111, 0.0111, 0.0219},
                             {0, 0, 0.09465, 0, 1, 0, 0.1879, 0, 0.0823, 0, 0.00171, 0.00171, 0.0033822}};
constexpr long kArmRows = 300000;

exoid::ident::ChainModel armChain() {
  exoid::ident::ChainModel m;
  m.name = "arm6";
  for (int i = 0; i < 6; ++i) {
    exoid::ident::ChainJoint j;
    j.name = "j" + std::to_string(i + 1);
    j.link = "l" + std::to_string(i + 1);
    j.parent_p_joint_m = Eigen::Vector3d(kArm[i].x, kArm[i].y, kArm[i].z);
    j.axis = Eigen::Vector3d(kArm[i].ax, kArm[i].ay, kArm[i].az);
    m.joints.push_back(j);
  }
  return m;
}

const std::string& armUrdf() {
  static const std::string path = [] {
    const std::string p = (std::filesystem::temp_directory_path() / "exoid_long_log_bench_arm6.urdf").string();
    std::FILE* f = std::fopen(p.c_str(), "w");
    std::fprintf(f, "<?xml version=\"1.0\"?>\n<robot name=\"arm6\">\n  <link name=\"base\"/>\n");
    for (int i = 0; i < 6; ++i) {
      const ArmLink& l = kArm[i];
      std::fprintf(f,
                   "  <joint name=\"j%d\" type=\"revolute\"><parent link=\"%s\"/><child link=\"l%d\"/><origin xyz=\"%.17g %.17g %.17g\"/>"
                   "<axis xyz=\"%g %g %g\"/><limit lower=\"-6.28\" upper=\"6.28\" effort=\"150\" velocity=\"3.15\"/>"
                   "<dynamics damping=\"0.2\" friction=\"0.5\"/></joint>\n"
                   "  <link name=\"l%d\"><inertial><mass value=\"%.17g\"/><origin xyz=\"%.17g %.17g %.17g\"/>"
                   "<inertia ixx=\"%.17g\" ixy=\"0\" ixz=\"0\" iyy=\"%.17g\" iyz=\"0\" izz=\"%.17g\"/></inertial></link>\n",
                   i + 1, i == 0 ? "base" : ("l" + std::to_string(i)).c_str(), i + 1, l.x, l.y, l.z, l.ax, l.ay, l.az, i + 1, l.mass, l.cx, l.cy,
                   l.cz, l.ixx, l.iyy, l.izz);
    }
    std::fprintf(f, "</robot>\n");
    std::fclose(f);
    std::atexit([] { std::filesystem::remove(std::filesystem::temp_directory_path() / "exoid_long_log_bench_arm6.urdf"); });
    return p;
  }();
  return path;
}

// The arm's log: each joint a three-harmonic motion, its exact derivatives, and the exact joint
// torques of the URDF's bodies with its friction (Newton-Euler).
const std::string& armLog() {
  static const std::string path = [] {
    const std::string p = (std::filesystem::temp_directory_path() / "exoid_long_log_bench_arm6.csv").string();
    const exoid::ident::ChainModel m = armChain();
    Eigen::VectorXd phi(m.standardParameterCount());
    const std::vector<exoid::ident::JointParameterLayout> layout = m.layout();
    for (int i = 0; i < 6; ++i) {
      const ArmLink& l = kArm[i];
      phi.segment<exoid::ident::kLinkParams>(layout[static_cast<std::size_t>(i)].link) = exoid::ident::linkParameters(
          l.mass, Eigen::Vector3d(l.cx, l.cy, l.cz), Eigen::Vector3d(l.ixx, l.iyy, l.izz).asDiagonal());
      phi.segment<2>(layout[static_cast<std::size_t>(i)].friction) << 0.5, 0.2;
    }
    std::FILE* f = std::fopen(p.c_str(), "w");
    std::fprintf(f, "t");
    for (const char* prefix : {"q_", "qd_", "qdd_", "tau_"}) {
      for (int i = 1; i <= 6; ++i) std::fprintf(f, ",%sj%d", prefix, i);
    }
    std::fprintf(f, "\n");
    exoid::core::Rng rng(2);
    double amp[6][3], freq[6][3], phase[6][3];
    for (int j = 0; j < 6; ++j) {
      for (int k = 0; k < 3; ++k) {
        amp[j][k] = rng.uniform(0.1, 0.4) / (k + 1);
        freq[j][k] = 2 * M_PI * rng.uniform(0.1, 0.6) * (k + 1);
        phase[j][k] = rng.uniform(0.0, 6.28);
      }
    }
    exoid::ident::ChainRegressorWorkspace work;
    Eigen::VectorXd q(6), qd(6), qdd(6), tau(6);
    for (long i = 0; i < kArmRows; ++i) {
      const double t = 1e-3 * static_cast<double>(i);
      q.setZero();
      qd.setZero();
      qdd.setZero();
      for (int j = 0; j < 6; ++j) {
        for (int k = 0; k < 3; ++k) {
          const double s = std::sin(freq[j][k] * t + phase[j][k]), c = std::cos(freq[j][k] * t + phase[j][k]);
          q[j] += amp[j][k] * s;
          qd[j] += amp[j][k] * freq[j][k] * c;
          qdd[j] -= amp[j][k] * freq[j][k] * freq[j][k] * s;
        }
      }
      exoid::ident::chainInverseDynamicsInto(m, q, qd, qdd, exoid::ident::ChainBaseMotion::still(m), phi, work, tau);
      std::fprintf(f, "%.17g", t);
      for (const Eigen::VectorXd* v : {&q, &qd, &qdd, &tau}) {
        for (int j = 0; j < 6; ++j) std::fprintf(f, ",%.17g", (*v)[j]);
      }
      std::fprintf(f, "\n");
    }
    std::fclose(f);
    std::atexit([] { std::filesystem::remove(std::filesystem::temp_directory_path() / "exoid_long_log_bench_arm6.csv"); });
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
// The arm's log through the library as identify processes it (its base parameters, the band
// chosen from the record, blocks on every core), then LS.
void BM_ChainLsEndToEnd(benchmark::State& state) {
  const std::string& path = armLog();
  const exoid::ident::Robot robot = exoid::ident::chainRobot(armChain());
  exoid::ident::CsvReadOptions read;
  read.joints = robot.jointNames();
  exoid::ident::SignalOptions o = identifyDefaults();
  o.threads = 0;
  Eigen::VectorXd x;
  for (auto _ : state) {
    const exoid::ident::RecordRows p = exoid::ident::processRecord(exoid::ident::readDatasetCsv(path, read), robot, o);
    x = exoid::ident::solveLeastSquares(p.W, p.y).x;
    benchmark::DoNotOptimize(x.data());
  }
  const double file_MB = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
  state.counters["peak_rss_MB"] = peakRssMB();
  state.counters["file_MB"] = file_MB;
  state.counters["peak_over_file"] = peakRssMB() / file_MB;
}
BENCHMARK(BM_ChainLsEndToEnd)->Unit(benchmark::kMillisecond)->UseRealTime();

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
ChildRun runExoidIdentify(const std::string& log, const std::string& model = "") {
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);  // the report, and the warnings a synthetic log earns
    std::freopen("/dev/null", "w", stderr);
    if (model.empty()) {
      execl(EXOID_BINARY, EXOID_BINARY, "identify", "--data", log.c_str(), "--method", "ls", static_cast<char*>(nullptr));
    } else {
      execl(EXOID_BINARY, EXOID_BINARY, "identify", "--model", model.c_str(), "--data", log.c_str(), "--method", "ls",
            static_cast<char*>(nullptr));
    }
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

// `exoid identify --model arm6.urdf --method ls` on the arm's 300,000 rows against `exoid identify
// --method ls` on the 2-link leg's 1,000,000, alternated in one run (this machine is shared): their
// time ratio, and the arm's peak memory against its file's size.
void BM_CliChainAgainstLeg(benchmark::State& state) {
  const std::string &leg = bigLog(), &arm = armLog(), &urdf = armUrdf();
  double leg_s = 0, arm_s = 0, arm_peak_MB = 0, leg_peak_MB = 0;
  for (auto _ : state) {
    const ChildRun a = runExoidIdentify(leg), b = runExoidIdentify(arm, urdf);
    if (a.wall_s < 0 || b.wall_s < 0) {
      state.SkipWithError("exoid identify failed");
      return;
    }
    leg_s += a.wall_s;
    arm_s += b.wall_s;
    leg_peak_MB = std::max(leg_peak_MB, a.peak_rss_MB);
    arm_peak_MB = std::max(arm_peak_MB, b.peak_rss_MB);
    state.SetIterationTime(b.wall_s);
  }
  const double n = static_cast<double>(state.iterations());
  const double arm_file_MB = static_cast<double>(std::filesystem::file_size(arm)) / 1e6;
  state.counters["leg_1M_s"] = leg_s / n;
  state.counters["arm_300k_s"] = arm_s / n;
  state.counters["arm_over_leg"] = arm_s / leg_s;
  state.counters["leg_peak_rss_MB"] = leg_peak_MB;
  state.counters["arm_peak_rss_MB"] = arm_peak_MB;
  state.counters["arm_file_MB"] = arm_file_MB;
  state.counters["arm_peak_over_file"] = arm_peak_MB / arm_file_MB;
}
BENCHMARK(BM_CliChainAgainstLeg)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(5);
#endif

}  // namespace

BENCHMARK_MAIN();

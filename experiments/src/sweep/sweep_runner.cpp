#include "exoid/experiments/sweep/sweep_runner.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/experiments/sweep/fault_injection.hpp"
#include "exoid/experiments/sweep/folder_lock.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/report/plots.hpp"
#include "exoid/experiments/sweep/progress.hpp"
#include "exoid/experiments/report/output_manifest.hpp"
#include "exoid/experiments/sweep/sweep_summary.hpp"
#include "exoid/experiments/sweep/robot_sweep.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>

namespace exoid::experiments {

namespace fs = std::filesystem;

namespace {

nlohmann::json readJson(const fs::path& p) { return readJsonFile(p.string()); }

// Finished jobs in DIR/runs, keyed by (cell, replicate). Files are renamed into place whole, so
// a file that does not parse was damaged afterwards (a disk error, a full disk on a filesystem
// without atomic rename, a user's editor): it is removed with a warning and its run redone.
// Temporaries of a killed run are removed.
std::map<std::pair<int, int>, fs::path> finishedJobs(const fs::path& dir, std::ostream* log = nullptr) {
  std::map<std::pair<int, int>, fs::path> out;
  const fs::path runs = dir / "runs";
  if (!fs::exists(runs)) return out;
  for (const auto& e : fs::directory_iterator(runs)) {
    const std::string name = e.path().filename().string();
    if (const auto id = parseJobFileName(name)) {
      std::string problem;
      try {
        const nlohmann::json j = readJson(e.path());
        if (j.value("cell", -1) != id->cell || j.value("replicate", -1) != id->replicate || !j.contains("status")) {
          problem = "it does not hold run (" + core::toText(id->cell) + ", " + core::toText(id->replicate) + ")";
        }
      } catch (const std::exception& err) {
        problem = fs::file_size(e.path()) == 0 ? std::string("it is empty") : err.what();
      }
      if (problem.empty()) {
        out[{id->cell, id->replicate}] = e.path();
      } else if (log != nullptr) {
        *log << "warning: " << e.path().string() << " is damaged (" << problem << "); redoing that run\n";
        std::error_code ec;
        fs::remove(e.path(), ec);
      } else {
        throw std::runtime_error(e.path().string() + " is damaged (" + problem +
                                 "); rerun `exoid sweep` on that shard's folder to redo the run");
      }
    } else if (name.find(".tmp.") != std::string::npos) {
      std::error_code ec;
      fs::remove(e.path(), ec);
    }
  }
  return out;
}

std::vector<nlohmann::json> readJobs(const std::map<std::pair<int, int>, fs::path>& files) {
  std::vector<nlohmann::json> jobs;
  for (const auto& [id, path] : files) jobs.push_back(readJson(path));
  return jobs;
}

constexpr const char* kMarker = "complete.json";

// What the folder holds once every output is written; written last, removed first (so a folder
// without it is unfinished, whatever else it holds: a kill or a full disk mid-way).
nlohmann::json completionRecord(const fs::path& dir) {
  const fs::path p = dir / kMarker;
  if (!fs::exists(p)) return nullptr;
  try {
    return readJson(p);
  } catch (const std::exception&) {
    return nullptr;  // damaged: the outputs are rewritten
  }
}

// How many of a folder's runs failed, and the first one's message.
struct RunFailures {
  long failed = 0, runs = 0;
  std::string example;
};

RunFailures failuresOf(const std::vector<nlohmann::json>& jobs) {
  RunFailures f;
  f.runs = static_cast<long>(jobs.size());
  for (const nlohmann::json& j : jobs) {
    if (j.value("status", "") != "ok" && !f.failed++) {
      f.example = "cell " + core::toText(j.value("cell", -1)) + " replicate " + core::toText(j.value("replicate", -1)) +
                  ": " + j.value("message", std::string("(no message)"));
    }
  }
  return f;
}

// Writes the tables, the plots, `timing` and then the completion marker (a plot failure is a
// warning, and the marker says the plots are missing, so a rerun retries them). The marker keeps
// the failures, so a rerun with nothing to do reports them without reading every run again.
RunFailures writeOutputs(const SweepLayout& layout, const std::vector<nlohmann::json>& jobs, const fs::path& dir, bool plots,
                         const nlohmann::json& timing, std::ostream& log) {
  std::error_code ec;
  fs::remove(dir / kMarker, ec);
  writeSweepTables(layout, jobs, dir.string());
  bool plots_written = layout.chain;  // a chain sweep has no figures: its tables are the output
  if (plots && !layout.chain) {
    try {
      runPlotScript("sweep_plots.py", {(dir / "summary.json").string(), dir.string()});
      plots_written = true;
    } catch (const std::exception& e) {
      log << "warning: " << e.what() << " (the runs and tables are complete; a rerun retries the plots)\n";
    }
    testKillPoint("sweep-plots");
  }
  writeJsonFile((dir / "timing.json").string(), timing);
  const RunFailures failures = failuresOf(jobs);
  std::vector<std::string> outputs = {"runs.csv", "summary.json", "summary.csv", "summary.md", "timing.json"};
  if (plots_written) {
    for (const std::string& png : pngFilesIn(dir.string())) outputs.push_back(png);
  }
  // Every output with its size and SHA-256: a rerun checks them before it says "complete".
  writeJsonFile((dir / kMarker).string(), {{"runs", failures.runs}, {"failed_runs", failures.failed},
                                           {"failure_example", failures.example}, {"plots", plots_written},
                                           {"outputs", outputManifest(dir.string(), outputs)},
                                           {"tool", toolJson()}});
  return failures;
}

// The outputs of a finished folder that are not as its complete.json lists them, each said; with
// keep_edits a changed one is refused (nothing is rewritten), else all are rewritten.
std::vector<OutputProblem> checkFinishedOutputs(const fs::path& dir, const nlohmann::json& marker, bool keep_edits, std::ostream& log) {
  if (!marker.is_object()) return {};
  return announceRewrites(dir.string(), marker.value("outputs", nlohmann::json()), keep_edits, "the runs", log);
}

// A finished folder with failed runs still exits non-zero, however often it is rerun.
void throwIfRunsFailed(const RunFailures& f, const fs::path& dir) {
  if (f.failed == 0) return;
  throw std::runtime_error(core::toText(f.failed) + " of " + core::toText(f.runs) + " runs failed (e.g. " + f.example + "); " +
                           (f.failed == f.runs ? "no run succeeded" : "the summary in " + dir.string() + " covers the rest"));
}

// config.json must match (resume or merge into an existing folder); written when absent.
void claimFolder(const fs::path& dir, const nlohmann::json& resolved) {
  core::prepareOutputFolder((dir / "runs").string());
  const fs::path cfg = dir / "config.json";
  if (fs::exists(cfg)) {
    const nlohmann::json old = readJson(cfg);
    if (old.dump() != resolved.dump()) {
      std::string diff;
      for (const auto& [k, v] : resolved.items()) {
        if (!old.contains(k) || old[k].dump() != v.dump()) diff += (diff.empty() ? "" : ", ") + k;
      }
      throw std::invalid_argument("refusing to resume into " + dir.string() + ": its config.json differs from this sweep's "
                                  "resolved configuration (in: " + (diff.empty() ? std::string("keys") : diff) +
                                  "). Use another --out, or the same config and flags as before.");
    }
  } else {
    writeJsonFile(cfg.string(), resolved);
  }
}

}  // namespace

ShardSpec parseShard(const std::string& s) {
  const auto slash = s.find('/');
  ShardSpec sh;
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    std::size_t used = 0;
    sh.index = std::stoi(s.substr(0, slash), &used);
    if (used != slash) throw std::invalid_argument("trailing characters");
    sh.count = std::stoi(s.substr(slash + 1), &used);
    if (used != s.size() - slash - 1) throw std::invalid_argument("trailing characters");
  } catch (const std::exception&) {
    throw std::invalid_argument("--shard expects K/N (e.g. 0/4), got '" + s + "'");
  }
  if (sh.count < 1 || sh.index < 0 || sh.index >= sh.count) {
    throw std::invalid_argument("--shard K/N needs 0 <= K < N, got '" + s + "'");
  }
  return sh;
}

std::optional<ShardSpec> shardFromEnvironment() {
  const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
  const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
  if (!id || !count) return std::nullopt;
  const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
  const int k = std::atoi(id) - (min ? std::atoi(min) : 0);
  return parseShard(core::toText(k) + "/" + count);
}

std::vector<JobId> shardJobs(const SweepConfig& c, ShardSpec shard) {
  std::vector<JobId> out;
  const int cells = c.numCells();
  for (int cell = shard.index; cell < cells; cell += shard.count) {
    for (int r = 0; r < c.seeds; ++r) out.push_back({cell, r});
  }
  return out;
}

namespace {

// shard.json must match (resume); written when absent.
void claimShard(const fs::path& dir, ShardSpec shard) {
  const nlohmann::json shard_json = {{"index", shard.index}, {"count", shard.count}};
  const fs::path shard_file = dir / "shard.json";
  if (fs::exists(shard_file) && readJson(shard_file).dump() != shard_json.dump()) {
    throw std::invalid_argument("refusing to resume into " + dir.string() + ": it holds shard " +
                                readJson(shard_file)["index"].dump() + "/" + readJson(shard_file)["count"].dump() +
                                ", this run is shard " + shard.text());
  }
  writeJsonFile(shard_file.string(), shard_json);
}

// A rerun of a finished shard whose outputs are complete: says so (and still fails when runs did).
bool finishedBefore(const fs::path& dir, const SweepRunOptions& o, const SweepRunReport& rep, bool pending, std::ostream& log) {
  const nlohmann::json marker = completionRecord(dir);
  if (pending || !marker.is_object() || marker.value("runs", -1L) != rep.jobs || (!marker.value("plots", false) && o.plots) ||
      !checkFinishedOutputs(dir, marker, o.keep_edits, log).empty()) {
    return false;
  }
  log << "exoid sweep: all " << rep.jobs << " runs of shard " << o.shard.text() << " in " << dir.string()
      << " are finished and its outputs complete; nothing to do.\n";
  throwIfRunsFailed({marker.value("failed_runs", 0L), rep.jobs, marker.value("failure_example", std::string())}, dir);
  return true;
}

void announceSweep(const SweepConfig& config, const SweepRunOptions& o, const SweepRunReport& rep, bool pending, int threads,
                   const fs::path& dir, std::ostream& log) {
  log << "exoid sweep" << (config.isChain() ? " --model " + config.model : std::string()) << ": " << config.numCells() << " cells x "
      << config.seeds << " seeds x " << config.methodNames().size()
      << " methods; shard " << o.shard.text() << ": " << rep.jobs << " runs";
  if (rep.skipped) log << " (" << rep.skipped << " already finished, resuming)";
  if (!pending) log << "; writing the missing outputs";
  log << ", " << threads << " threads -> " << dir.string() << '\n' << std::flush;
}

// Runs `pending` on `threads` workers, each job's record written to DIR/runs as it finishes; the
// first error stops the workers (after their current job) and is rethrown.
void runJobs(const SweepConfig& config, const std::vector<JobId>& pending, const fs::path& dir, int threads, Progress& progress) {
  std::atomic<std::size_t> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;
  auto worker = [&] {
    for (;;) {
      const std::size_t i = next.fetch_add(1);
      if (i >= pending.size()) return;
      {
        std::lock_guard<std::mutex> guard(error_mutex);
        if (error) return;
      }
      try {
        const nlohmann::json j = runSweepJob(config, pending[i]);
        writeJsonFile((dir / "runs" / jobFileName(pending[i])).string(), j);
        progress.tick();
      } catch (...) {
        std::lock_guard<std::mutex> guard(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  const int n_workers = std::min<int>(threads, static_cast<int>(std::max<std::size_t>(pending.size(), 1)));
  for (int t = 0; t < n_workers; ++t) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
  progress.finish();
  if (error) std::rethrow_exception(error);
}

// This shard's runs: those validated at the start and those just written (no second folder scan).
std::vector<nlohmann::json> shardRecords(const std::vector<JobId>& jobs, const std::map<std::pair<int, int>, fs::path>& done,
                                         const fs::path& dir) {
  std::map<std::pair<int, int>, fs::path> mine;
  for (const JobId& j : jobs) {
    const auto it = done.find({j.cell, j.replicate});
    mine[{j.cell, j.replicate}] = it != done.end() ? it->second : dir / "runs" / jobFileName(j);
  }
  return readJobs(mine);
}

double runsPerMinute(const SweepRunReport& rep) {
  return rep.ran > 0 ? 60.0 * static_cast<double>(rep.ran) / rep.wall_time_s : 0.0;
}

nlohmann::json timingJson(const SweepConfig& config, const SweepRunOptions& o, const SweepRunReport& rep, int threads,
                          const std::vector<nlohmann::json>& records) {
  double job_time = 0.0;
  for (const nlohmann::json& j : records) job_time += j.at("wall_time_s").get<double>();
  const double per_minute = runsPerMinute(rep);
  return {{"threads", threads}, {"shard", o.shard.text()}, {"runs", rep.jobs}, {"runs_this_invocation", rep.ran},
          {"runs_resumed", rep.skipped}, {"wall_time_s", rep.wall_time_s}, {"runs_per_minute", per_minute},
          {"identifications_per_minute", per_minute * static_cast<double>(config.methodNames().size())},
          {"sum_of_run_wall_times_s", job_time}};
}

}  // namespace

SweepRunReport runSweep(const SweepConfig& given, const SweepRunOptions& o, std::ostream& log) {
  given.validate();
  ident::Stopwatch clock;
  const fs::path dir(o.out);
  core::prepareOutputFolder((dir / "runs").string());
  const FolderLock lock(dir.string(), "exoid sweep --out " + dir.string() + " (shard " + o.shard.text() + ")");
  // A chain's optimised record is designed here when the config gives none (the same design
  // again on a resume: it is deterministic, and config.json holds its coefficients).
  const SweepConfig config = withChainDesign(given, dir.string(), log);
  const SweepLayout layout = layoutOf(config);
  claimFolder(dir, layout.resolved);
  claimShard(dir, o.shard);

  const std::vector<JobId> jobs = shardJobs(config, o.shard);
  const auto done = finishedJobs(dir, &log);
  std::vector<JobId> pending;
  for (const JobId& j : jobs) {
    if (!done.count({j.cell, j.replicate})) pending.push_back(j);
  }
  SweepRunReport rep;
  rep.jobs = static_cast<long>(jobs.size());
  rep.skipped = rep.jobs - static_cast<long>(pending.size());
  if (finishedBefore(dir, o, rep, !pending.empty(), log)) return rep;
  const int threads = std::max(1, o.threads > 0 ? o.threads : static_cast<int>(std::thread::hardware_concurrency()));
  announceSweep(config, o, rep, !pending.empty(), threads, dir, log);
  Progress progress(rep.jobs, rep.skipped, "runs", stderr, o.progress_tty);
  runJobs(config, pending, dir, threads, progress);
  rep.ran = static_cast<long>(pending.size());

  const std::vector<nlohmann::json> records = shardRecords(jobs, done, dir);
  rep.wall_time_s = clock.seconds();
  const nlohmann::json timing = timingJson(config, o, rep, threads, records);
  const RunFailures failures = writeOutputs(layout, records, dir, o.plots, timing, log);
  log << "exoid sweep: " << rep.ran << " runs in " << fmt(rep.wall_time_s, 4) << " s (" << fmt(runsPerMinute(rep), 4)
      << " runs/min); summary: " << (dir / "summary.md").string() << '\n';
  throwIfRunsFailed(failures, dir);
  return rep;
}

void mergeSweeps(const std::vector<std::string>& shard_dirs, const std::string& out, bool plots, std::ostream& log, bool keep_edits) {
  if (shard_dirs.empty()) throw std::invalid_argument("exoid merge: give at least one shard folder");
  ident::Stopwatch clock;
  nlohmann::json resolved;
  std::map<std::pair<int, int>, fs::path> files;
  nlohmann::json shard_timing = nlohmann::json::array();
  for (const std::string& d : shard_dirs) {
    const fs::path cfg = fs::path(d) / "config.json";
    if (!fs::exists(cfg)) throw std::invalid_argument("exoid merge: " + d + " is not a sweep folder (no config.json)");
    const nlohmann::json c = readJson(cfg);
    if (resolved.is_null()) {
      resolved = c;
    } else if (c.dump() != resolved.dump()) {
      throw std::invalid_argument("exoid merge: " + d + "/config.json differs from " + shard_dirs.front() +
                                  "/config.json: shards of one sweep must share the configuration");
    }
    for (const auto& [id, p] : finishedJobs(d)) {
      const auto [it, inserted] = files.emplace(id, p);
      // The same run in two folders (a shard rerun into another folder, overlapping shards): fine
      // if it is the same result, refused if not (which one would be right?).
      if (!inserted && withoutWallTimes(readJson(it->second)) != withoutWallTimes(readJson(p))) {
        throw std::runtime_error("exoid merge: " + it->second.string() + " and " + p.string() +
                                 " hold different results for the same run (cell " + core::toText(id.first) +
                                 ", replicate " + core::toText(id.second) +
                                 "); were they made by different exoid versions or machines? Merge folders of one sweep only.");
      }
    }
    if (fs::exists(fs::path(d) / "timing.json")) shard_timing.push_back(readJson(fs::path(d) / "timing.json"));
  }
  const SweepLayout layout = layoutFromJson(resolved);
  long missing = 0;
  std::string example;
  for (int cell = 0; cell < static_cast<int>(layout.cells.size()); ++cell) {
    for (int r = 0; r < layout.seeds; ++r) {
      if (!files.count({cell, r})) {
        if (!missing++) example = "cell " + core::toText(cell) + " replicate " + core::toText(r);
      }
    }
  }
  if (missing) {
    throw std::runtime_error("exoid merge: " + core::toText(missing) + " runs are missing (e.g. " + example +
                             "); did every shard finish? Re-run the missing shards (they resume), then merge again.");
  }
  const fs::path dir(out);
  core::prepareOutputFolder((dir / "runs").string());
  const FolderLock lock(dir.string(), "exoid merge --out " + dir.string());
  claimFolder(dir, resolved);
  std::vector<nlohmann::json> jobs = readJobs(files);
  for (const nlohmann::json& j : jobs) {
    const JobId id{j.at("cell").get<int>(), j.at("replicate").get<int>()};
    const fs::path target = dir / "runs" / jobFileName(id);
    if (!fs::exists(target)) writeJsonFile(target.string(), j);
  }
  writeJsonFile((dir / "shard.json").string(), {{"index", 0}, {"count", 1}});
  checkFinishedOutputs(dir, completionRecord(dir), keep_edits, log);  // a merge into a merged folder: say what it replaces
  const RunFailures failures = writeOutputs(layout, jobs, dir, plots,
                                            {{"merged_from", shard_dirs}, {"shards", shard_timing}, {"merge_wall_time_s", clock.seconds()}}, log);
  log << "exoid merge: " << jobs.size() << " runs from " << shard_dirs.size() << " folders -> " << (dir / "summary.md").string() << '\n';
  throwIfRunsFailed(failures, dir);
}

}  // namespace exoid::experiments

#include "exoid/experiments/protocol/robot_reproduce.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/core/random.hpp"
#include "exoid/experiments/protocol/excitation_design.hpp"
#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/commands/commands.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/report/output_manifest.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace exoid::experiments {
namespace {

// Runs an identification, its exit-3 verdict kept as a note (the JSON is written first).
std::string identifyNoting(const ChainIdentifyArgs& a) {
  try {
    identifyChain(a);
    return "";
  } catch (const UnusableResult& e) {
    return e.what();
  }
}

std::string percent(double estimate, double truth) {
  return std::abs(truth) > 0.0 ? fixed(100.0 * (estimate - truth) / std::abs(truth), 2) : "-";
}

// Median |relative error| (%) over the base parameters with a non-zero truth.
double medianAbsError(const std::vector<double>& estimate, const std::vector<double>& truth) {
  std::vector<double> e;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (std::abs(truth[i]) > 0.0) e.push_back(100.0 * std::abs(estimate[i] - truth[i]) / std::abs(truth[i]));
  }
  if (e.empty()) return 0.0;
  std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
  return e[e.size() / 2];
}

// 1. The design (exoid excite --model); returns its file.
std::string designFitRecord(const ChainReproduceArgs& a, const std::string& dir) {
  ExciteRequest ex;
  ex.model = a.sim.model_path;
  ex.selection = a.sim.selection;
  ex.out = dir + "design.json";
  ex.options.seed = core::deriveSeed(a.seed, 0);
  ex.options.restarts = a.design_restarts;
  ex.plot = a.plots;
  excite(ex);
  return ex.out;
}

// 2. The records: the design (fit; the last stage), another motion (validation), and one record
// per segmental stage, the joints above its first moving joint locked.
struct ChainRecords {
  nlohmann::json fit_sidecar;                                 ///< the fit record's: its joints and name
  std::vector<std::string> joints;
  std::vector<std::pair<std::string, std::string>> stages;  ///< (first moving joint, file), distal first
};

ChainRecords simulateRecords(const ChainReproduceArgs& a, const std::string& dir, const std::string& design) {
  sim::ChainSimConfig c = a.sim;
  c.trajectory = readExcitationFile(design).series;
  c.seed = core::deriveSeed(a.seed, 1);
  simulateChainToFiles(c, dir + "fit.csv");
  sim::ChainSimConfig check = a.sim;
  check.seed = core::deriveSeed(a.seed, 2);  // the default trajectory of this seed: another motion
  simulateChainToFiles(check, dir + "check.csv");
  ChainRecords r;
  r.fit_sidecar = readJsonFile(dir + "fit.json");
  r.joints = r.fit_sidecar["model"]["joints"].get<std::vector<std::string>>();
  for (std::size_t j = r.joints.size() - 1; j >= 1; --j) {
    sim::ChainSimConfig st = a.sim;
    st.seed = core::deriveSeed(a.seed, 10 + j);
    st.locked.assign(r.joints.begin(), r.joints.begin() + static_cast<std::ptrdiff_t>(j));
    const std::string file = dir + "stage_" + r.joints[j] + ".csv";
    simulateChainToFiles(st, file);
    r.stages.emplace_back(r.joints[j], file);
  }
  return r;
}

// 3. Identification: one fit of the designed record (identify.json), and the segmental strategy
// (segmental.json); each one's exit-3 verdict, empty when usable.
struct ChainIdentifications {
  std::string one_fit_note, segmental_note;
};

ChainIdentifications identifyRecords(const ChainReproduceArgs& a, const std::string& dir, const ChainRecords& records) {
  ChainIdentifyArgs id;
  id.model = a.sim.model_path;
  id.selection = a.sim.selection;
  id.data = {dir + "fit.csv"};
  id.validate = {dir + "check.csv"};
  id.truth = dir + "fit.json";
  id.json_out = dir + "identify.json";
  if (a.plots) id.plot = dir + "fit.png";
  id.signals = defaultIdentifySignals();
  id.methods = a.methods;
  ChainIdentifications notes;
  notes.one_fit_note = identifyNoting(id);
  ChainIdentifyArgs seg = id;
  seg.plot.clear();
  seg.stages = records.stages;
  seg.json_out = dir + "segmental.json";
  // The instrumental-variable methods fit one record whole (their instruments are the record's).
  for (ident::Method iv : {ident::Method::kIvBand, ident::Method::kIdimIv}) {
    seg.methods.erase(std::remove(seg.methods.begin(), seg.methods.end(), iv), seg.methods.end());
  }
  notes.segmental_note = identifyNoting(seg);
  return notes;
}

using NamedEstimates = std::vector<std::pair<std::string, std::vector<double>>>;

// Every base parameter: its truth and each estimate's error (%).
void writeErrorTable(std::ostream& md, const std::vector<std::string>& names, const std::vector<double>& truth, const NamedEstimates& fits,
                     const NamedEstimates& staged) {
  md << "| base parameter | truth |";
  for (const auto& f : fits) md << " " << f.first << " |";
  for (const auto& f : staged) md << " segmental " << f.first << " |";
  md << "\n|---|---|";
  for (std::size_t k = 0; k < fits.size() + staged.size(); ++k) md << "---|";
  md << "\n";
  for (std::size_t i = 0; i < names.size(); ++i) {
    md << "| " << names[i] << " | " << fmt(truth[i], 6) << " |";
    for (const auto& f : fits) md << " " << percent(f.second[i], truth[i]) << " |";
    for (const auto& f : staged) md << " " << percent(f.second[i], truth[i]) << " |";
    md << "\n";
  }
}

// Each method's median |error| and validation RMS per joint (one fit's, then the stages'), into the
// report and the printed table.
void writeSummaryTable(std::ostream& md, TextTable& t, const std::vector<double>& truth, const NamedEstimates& fits,
                       const NamedEstimates& staged, const nlohmann::json& val, const nlohmann::json& staged_val) {
  md << "\n## Summary\n\n| method | median abs error (%) | validation RMS per joint (N m) |\n|---|---|---|\n";
  const auto rows = [&](const NamedEstimates& estimates, const nlohmann::json& v, const std::string& prefix) {
    for (const auto& f : estimates) {
      std::string rms;
      if (f.first == "ls") {
        for (const auto& jv : v["joints"]) rms += (rms.empty() ? "" : ", ") + fmt(jv["rms_error_Nm"].get<double>(), 4);
      } else {
        for (double x : v["methods_rms_error_Nm"][f.first]) rms += (rms.empty() ? "" : ", ") + fmt(x, 4);
      }
      const std::string med = fixed(medianAbsError(f.second, truth), 2);
      md << "| " << prefix << f.first << " | " << med << " | " << rms << " |\n";
      t.addRow({prefix + f.first, med, rms});
    }
  };
  rows(fits, val, "");
  rows(staged, staged_val, "segmental ");
  md << "\n";
}

// 4. The report (report.md) from identify.json and segmental.json; the summary printed.
void writeChainReport(const ChainReproduceArgs& a, const std::string& dir, const std::string& design, const ChainRecords& records,
                      const ChainIdentifications& notes) {
  const nlohmann::json one = readJsonFile(dir + "identify.json"), sg = readJsonFile(dir + "segmental.json");
  const std::vector<std::string> names = one["base_parameters"]["names"];
  const std::vector<double> truth = one["base_parameters"]["truth"];
  NamedEstimates fits = {{"ls", one["base_parameters"]["ls"]}};
  for (auto it = one["methods"].begin(); it != one["methods"].end(); ++it) fits.emplace_back(it.key(), it.value()["beta"].get<std::vector<double>>());
  NamedEstimates staged = {{"ls", sg["base_parameters"]["ls"]}};
  for (auto it = sg["methods"].begin(); it != sg["methods"].end(); ++it) staged.emplace_back(it.key(), it.value()["beta"].get<std::vector<double>>());
  std::ostringstream md;
  md << "# exoid reproduce --model " << records.fit_sidecar["model"]["name"].get<std::string>() << "\n\n"
     << "Model `" << std::filesystem::path(a.sim.model_path).filename().string()
     << (a.sim.selection.empty() ? "" : " " + a.sim.selection.options()) << "` (" << records.joints.size() << " joints, " << names.size()
     << " base parameters), seed " << a.seed << ", " << toolJson().dump() << ".\n\n"
     << "Records (" << fmt(a.sim.duration_s, 4) << " s at " << fmt(1.0 / a.sim.dt_s, 4) << " Hz; encoder noise "
     << fmt(a.sim.sensors.noise_q_deg, 3) << " deg, resolution " << fmt(a.sim.sensors.quantisation_deg, 3) << " deg, torque noise "
     << fmt(a.sim.sensors.noise_tau_Nm, 3) << " N m): `fit.csv` the design `design.json` (condition number "
     << fmt(readJsonFile(design)["score"]["condition_number"].get<double>(), 4) << "), `check.csv` another motion (validation), ";
  for (const auto& [joint, file] : records.stages) md << "`stage_" << joint << ".csv` (joints above " << joint << " locked), ";
  md << "each with its sidecar (settings, seed, truth). The stage records follow the simulator's default motion of "
        "their seed, not a design (exoid excite --first-moving JOINT designs one), as the paper's knee-only record was not one: "
        "a stage's error reflects its record's excitation as much as the strategy.\n\n## Every base parameter, error against the truth (%)\n\n";
  writeErrorTable(md, names, truth, fits, staged);
  TextTable t({"method", "median |err| %", "validation RMS (N m), per joint"});
  writeSummaryTable(md, t, truth, fits, staged, one["validation"].front(), sg["validation"].front());
  if (!notes.one_fit_note.empty()) md << "One fit, not usable (exit 3 of identify): " << notes.one_fit_note << "\n\n";
  if (!notes.segmental_note.empty()) md << "Segmental strategy, not usable (exit 3 of identify): " << notes.segmental_note << "\n\n";
  md << "Files: `identify.json`, `segmental.json` (every estimate, status and condition number)"
     << (a.plots ? ", `fit.png` (measured and predicted torques of the validation record), `design.png` and `design_series.csv` (the "
                   "design against the limits)"
                 : "")
     << ".\n";
  core::writeFileAtomically(dir + "report.md", [&](std::ostream& o) { o << md.str(); });
  std::cout << "\n";
  t.print(std::cout);
}

}  // namespace

int reproduceChain(const ChainReproduceArgs& a) {
  core::prepareOutputFolder(a.out);
  startFolderRun(a.out, a.keep_edits, std::cout);
  const auto started = std::filesystem::file_time_type::clock::now() - std::chrono::seconds(1);
  const std::string dir = a.out + "/";
  std::cout << "exoid reproduce --model " << a.sim.model_path << (a.sim.selection.empty() ? "" : " " + a.sim.selection.options()) << ": design, " << a.sim.duration_s
            << " s records, identification by every method, one fit and the segmental strategy\n"
            << std::flush;
  const std::string design = designFitRecord(a, dir);
  const ChainRecords records = simulateRecords(a, dir, design);
  const ChainIdentifications notes = identifyRecords(a, dir, records);
  writeChainReport(a, dir, design, records, notes);
  finishFolderRun(a.out, started, {{"command", "reproduce --model"}, {"seed", a.seed}, {"tool", toolJson()}});
  std::cout << "\nreport: " << dir << "report.md\n";
  return 0;
}

}  // namespace exoid::experiments

#include "exoid/experiments/sweep/sweep_config.hpp"

#include "exoid/core/format.hpp"
#include "exoid/experiments/commands/robot_commands.hpp"
#include "exoid/experiments/protocol/excitation_io.hpp"

#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/protocol/reproduce.hpp"
#include "exoid/experiments/report/cells.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/core/random.hpp"
#include "exoid/core/sha256.hpp"
#include "exoid/sim/motor_rig.hpp"
#include "exoid/sim/model.hpp"
#include "exoid/sim/serial_chain.hpp"
#include "exoid/sim/sidecar.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <set>
#include <sstream>

namespace exoid::experiments {

namespace {

std::string where(const SweepConfig& c, const std::string& key) {
  const auto it = c.origin.find(key);
  return it == c.origin.end() ? "'" + key + "'" : "'" + key + "' (" + it->second + ")";
}

void checkList(const SweepConfig& c, const std::string& key, const std::vector<double>& v, double lo, double hi) {
  if (v.empty()) throw SweepConfigError(where(c, key) + ": the grid list is empty (give at least one level)");
  for (double x : v) {
    if (!std::isfinite(x)) throw SweepConfigError(where(c, key) + ": levels must be finite, got " + core::formatNumber(x, 17));
    if (x < lo) throw SweepConfigError(where(c, key) + ": levels must be >= " + core::formatNumber(lo, 17) + ", got " + core::formatNumber(x, 17));
    if (x > hi) throw SweepConfigError(where(c, key) + ": levels must be <= " + core::formatNumber(hi, 17) + ", got " + core::formatNumber(x, 17));
  }
  if (std::set<double>(v.begin(), v.end()).size() != v.size()) {
    throw SweepConfigError(where(c, key) + ": levels must be distinct");
  }
}

std::string at(const std::string& file, const toml::source_region& s) {
  return file + ":" + core::toText(s.begin.line) + ":" + core::toText(s.begin.column);
}

// Typed readers: each records the origin and throws naming the key on a wrong type.
struct Reader {
  const std::string& file;
  SweepConfig& c;
  // Read after every key: the methods' names mean different things for the APAL leg and a chain.
  std::optional<std::vector<std::string>> method_names;
  std::optional<std::string> model;

  std::string loc(const toml::node& n) const { return at(file, n.source()); }

  double number(const toml::node& n, const std::string& key) {
    c.origin[key] = loc(n);
    if (auto v = n.value<double>(); v && (n.is_floating_point() || n.is_integer())) return *v;
    throw SweepConfigError("'" + key + "' (" + loc(n) + "): expected a number");
  }
  std::int64_t integer(const toml::node& n, const std::string& key) {
    c.origin[key] = loc(n);
    if (n.is_integer()) return *n.value<std::int64_t>();
    throw SweepConfigError("'" + key + "' (" + loc(n) + "): expected an integer");
  }
  bool boolean(const toml::node& n, const std::string& key) {
    c.origin[key] = loc(n);
    if (n.is_boolean()) return *n.value<bool>();
    throw SweepConfigError("'" + key + "' (" + loc(n) + "): expected true or false");
  }
  std::vector<double> numbers(const toml::node& n, const std::string& key) {
    c.origin[key] = loc(n);
    std::vector<double> out;
    if (n.is_integer() || n.is_floating_point()) return {number(n, key)};
    const toml::array* a = n.as_array();
    if (!a) throw SweepConfigError("'" + key + "' (" + loc(n) + "): expected an array of numbers");
    for (const toml::node& e : *a) {
      if (!(e.is_integer() || e.is_floating_point())) {
        throw SweepConfigError("'" + key + "' (" + at(file, e.source()) + "): expected an array of numbers");
      }
      out.push_back(*e.value<double>());
    }
    c.origin[key] = loc(n);
    return out;
  }
  std::vector<std::string> strings(const toml::node& n, const std::string& key) {
    c.origin[key] = loc(n);
    const toml::array* a = n.as_array();
    if (!a) throw SweepConfigError("'" + key + "' (" + loc(n) + "): expected an array of strings");
    std::vector<std::string> out;
    for (const toml::node& e : *a) {
      if (!e.is_string()) throw SweepConfigError("'" + key + "' (" + at(file, e.source()) + "): expected an array of strings");
      out.push_back(*e.value<std::string>());
    }
    return out;
  }
};

}  // namespace

SweepConfig::SweepConfig() {
  base = defaultReproduceConfig();
  base.sim.duration_s = 5.0;
  // Every PSO and RLS-PSO result carries its optimality gaps (unconstrained and over its box).
}

void SweepConfig::setModel(const std::string& name_or_path, const std::string& origin_text) {
  origin["sweep.model"] = origin_text;
  model = name_or_path;
  chain_model_path.clear();
  if (name_or_path.empty() || name_or_path == "apal") return;
  const std::string path = sim::modelPathFor(name_or_path);
  try {
    if (sim::isApalLegModel(path)) return;
  } catch (const std::exception& e) {
    throw SweepConfigError(where(*this, "sweep.model") + ": " + e.what());
  }
  chain_model_path = path;
  // The chain rig has neither the APAL pedestal's compliant mount nor its cylinder, nor the
  // paper's records: the grid's defaults become the chain's where the file left them.
  if (!origin.count("grid.vibration_level")) vibration_level = {0.0};
  if (!origin.count("grid.cylinder_mass_scale")) cylinder_mass_scale = {0.0};
  if (!origin.count("grid.trajectories")) trajectories = {"optimised"};
}

void SweepConfig::setMethods(const std::vector<std::string>& names, const std::string& origin_text) {
  origin["sweep.methods"] = origin_text;
  const std::string key = "'sweep.methods' (" + origin_text + "): ";
  if (isChain()) {
    chain_methods.clear();
    for (const std::string& m : names) {
      try {
        chain_methods.push_back(ident::parseMethod(m));
      } catch (const std::invalid_argument& e) {
        throw SweepConfigError(key + e.what() + " (a chain model's sweep: ls, rls, pso, rls-pso, lad, iv-band, idim-iv)");
      }
    }
    return;
  }
  methods.clear();
  for (const std::string& m : names) {
    try {
      methods.push_back(parseVariant(m));
    } catch (const std::invalid_argument& e) {
      throw SweepConfigError(key + e.what());
    }
  }
}

std::vector<std::string> SweepConfig::methodNames() const {
  std::vector<std::string> names;
  if (isChain()) {
    for (ident::Method m : chain_methods) names.emplace_back(ident::toString(m));
  } else {
    for (Variant v : methods) names.emplace_back(toString(v));
  }
  return names;
}

namespace {

// What a chain sweep cannot take: the APAL rig's factors, records and processing keys.
void validateChain(const SweepConfig& c) {
  const std::string model = "a chain model's sweep (model " + c.model + ")";
  if (c.cylinder_mass_scale != std::vector<double>{0.0}) {
    throw SweepConfigError(where(c, "grid.cylinder_mass_scale") + ": " + model + " has no hydraulic cylinder: give [0] or leave the key out");
  }
  if (c.vibration_level != std::vector<double>{0.0} && !sim::hasCompliantMount(c.chain_model_path)) {
    throw SweepConfigError(where(c, "grid.vibration_level") + ": " + model + " stands on a rigid stand ('" + c.chain_model_path +
                           "' has no joint of class \"mount\" between the world and the chain, as models/leg3.xml's): give [0] or "
                           "leave the key out");
  }
  for (const char* key : {"simulation.ramp_s", "simulation.feedforward", "simulation.excitation_knee", "simulation.excitation_both",
                          "identification.cutoff_hz", "identification.filter"}) {
    if (c.origin.count(key)) {
      throw SweepConfigError(where(c, key) + ": is the APAL leg's; " + model +
                             " processes each record as `exoid identify --model` does (the band from the data) and takes "
                             "[simulation] duration_s, dt_s, excitation");
    }
  }
  if (c.trajectories.empty()) throw SweepConfigError(where(c, "grid.trajectories") + ": the grid list is empty (\"optimised\", \"default\")");
  for (const std::string& t : c.trajectories) {
    if (t != "optimised" && t != "default") {
      throw SweepConfigError(where(c, "grid.trajectories") + ": " + model + " takes \"optimised\" (one design for the sweep) or " +
                             "\"default\" (the simulator's motion of each run's seed), got \"" + t + "\"");
    }
  }
  if (std::set<std::string>(c.trajectories.begin(), c.trajectories.end()).size() != c.trajectories.size()) {
    throw SweepConfigError(where(c, "grid.trajectories") + ": levels must be distinct");
  }
  if (c.chain_methods.empty()) throw SweepConfigError(where(c, "sweep.methods") + ": name at least one method");
  if (std::set<ident::Method>(c.chain_methods.begin(), c.chain_methods.end()).size() != c.chain_methods.size()) {
    throw SweepConfigError(where(c, "sweep.methods") + ": methods must be distinct");
  }
  std::vector<std::string> joints;
  try {
    joints = sim::serialChainFromFile(c.chain_model_path, c.chain_selection).jointNames();
  } catch (const std::invalid_argument& e) {
    throw SweepConfigError(where(c, "sweep.model") + ": " + e.what() + " (a sweep's: [sweep] base, tip, lock)");
  }
  if (c.chain_design) {
    if (c.chain_design->joints != joints) {
      throw SweepConfigError(where(c, "simulation.excitation") + ": the design moves " + core::toText(c.chain_design->joints.size()) +
                             " joints (" + core::joined(c.chain_design->joints) + "); " + model + " has " + core::joined(joints) +
                             " (a design of another model?)");
    }
  }
  sim::ChainSimConfig s;
  s.model_path = c.chain_model_path;
  s.selection = c.chain_selection;
  s.duration_s = c.base.sim.duration_s;
  s.dt_s = c.base.sim.dt_s;
  try {
    s.validate();
    if (c.chain_design) c.chain_design->series.validate();
  } catch (const std::invalid_argument& e) {
    throw SweepConfigError(std::string("invalid [simulation] setting: ") + e.what());
  }
}

}  // namespace

void SweepConfig::validate() const {
  for (const char* key : {"sweep.base", "sweep.tip", "sweep.lock"}) {
    if (!origin.count(key)) continue;
    if (!isChain()) {
      throw SweepConfigError(where(*this, key) + ": chooses a chain out of a URDF's tree ([sweep] model = a URDF); the APAL leg's rig is its own");
    }
    if (!sim::isUrdfFile(chain_model_path)) {
      throw SweepConfigError(where(*this, key) + ": base, tip and lock choose a chain out of a URDF's tree; '" + chain_model_path +
                             "' is an MJCF, simulated as it is");
    }
  }
  if (origin.count("simulation.excitation") && !isChain()) {
    throw SweepConfigError(where(*this, "simulation.excitation") + ": is a chain model's design ([sweep] model = \"leg3\" or a file); "
                           "the APAL leg's are excitation_knee and excitation_both");
  }
  checkList(*this, "grid.torque_noise_Nm", torque_noise_Nm, 0.0, 1e3);
  checkList(*this, "grid.angle_noise_deg", angle_noise_deg, 0.0, 90.0);
  checkList(*this, "grid.quantisation_deg", quantisation_deg, 0.0, 90.0);
  checkList(*this, "grid.vibration_level", vibration_level, 0.0, 20.0);
  checkList(*this, "grid.cylinder_mass_scale", cylinder_mass_scale, 0.0, 10.0);
  checkList(*this, "grid.encoder_backlash_deg", encoder_backlash_deg, 0.0, 89.0);
  if (isChain()) {
    validateChain(*this);
  } else {
    validateApal();
  }
  try {
    base.band_rule.validate();
  } catch (const std::invalid_argument& e) {
    throw SweepConfigError(std::string("[identification] band_* (the band rule): ") + e.what());
  }
  if (seeds < 1 || seeds > 1000000) {
    throw SweepConfigError(where(*this, "sweep.seeds") + ": must be in [1, 1e6], got " + core::toText(seeds));
  }
  // Bounded before anything is allocated per run (a job list of 2^31 runs exhausts memory).
  constexpr double kMaxRuns = 1e7;
  if (static_cast<double>(numCells()) * seeds > kMaxRuns) {
    throw SweepConfigError(where(*this, "sweep.seeds") + ": " + core::toText(numCells()) + " cells x " +
                           core::toText(seeds) + " seeds is more than 1e7 runs; use fewer seeds or grid levels");
  }
}

void SweepConfig::validateApal() const {
  if (trajectories.empty()) throw SweepConfigError(where(*this, "grid.trajectories") + ": the grid list is empty (\"paper\", \"optimised\")");
  for (const std::string& t : trajectories) {
    if (t != "paper" && t != "optimised") {
      throw SweepConfigError(where(*this, "grid.trajectories") + ": expected \"paper\" or \"optimised\", got \"" + t + "\"");
    }
  }
  if (std::set<std::string>(trajectories.begin(), trajectories.end()).size() != trajectories.size()) {
    throw SweepConfigError(where(*this, "grid.trajectories") + ": levels must be distinct");
  }
  const bool optimised = std::count(trajectories.begin(), trajectories.end(), "optimised") > 0;
  if (optimised && !(optimised_knee && optimised_both)) {
    throw SweepConfigError(where(*this, "grid.trajectories") +
                           ": \"optimised\" needs both designs: set [simulation] excitation_knee and excitation_both "
                           "(exoid excite files; exoid ships experiments/configs/excitation_knee.json and excitation_both.json)");
  }

  if (methods.empty()) throw SweepConfigError(where(*this, "sweep.methods") + ": name at least one method");
  if (std::set<Variant>(methods.begin(), methods.end()).size() != methods.size()) {
    throw SweepConfigError(where(*this, "sweep.methods") + ": methods must be distinct");
  }
  try {
    for (const SweepCondition& cond : conditions()) protocolFor(cond, 1).validate();
  } catch (const std::invalid_argument& e) {
    throw SweepConfigError(std::string("invalid [simulation]/[identification] setting: ") + e.what());
  }
}

std::vector<SweepCondition> SweepConfig::conditions() const {
  std::vector<SweepCondition> out;
  for (const std::string& traj : trajectories)
    for (double play : encoder_backlash_deg)
      for (double cyl : cylinder_mass_scale)
        for (double vib : vibration_level)
          for (double qn : angle_noise_deg)
            for (double qq : quantisation_deg)
              for (double tn : torque_noise_Nm) out.push_back({tn, qn, qq, vib, cyl, play, traj});
  return out;
}

std::uint64_t SweepConfig::jobSeed(int cell, int replicate) const {
  // Trajectories vary slowest: cells of one level are a contiguous block, and the same position
  // in every block is the same noise condition.
  const int per_level = numCells() / static_cast<int>(std::max<std::size_t>(trajectories.size(), 1));
  return core::deriveSeed(core::deriveSeed(master_seed, static_cast<std::uint64_t>(cell % per_level)),
                            static_cast<std::uint64_t>(replicate));
}

ProtocolConfig SweepConfig::protocolFor(const SweepCondition& c, std::uint64_t seed) const {
  ProtocolConfig p = base;
  p.sim.sensors.noise_tau_Nm = c.torque_noise_Nm;
  p.sim.sensors.noise_q_deg = c.angle_noise_deg;
  p.sim.sensors.quantisation_deg = c.quantisation_deg;
  p.sim.variant.vibration_level = c.vibration_level;
  p.sim.variant.cylinder_mass_scale = c.cylinder_mass_scale;
  p.sim.sensors.encoder_backlash_deg = c.encoder_backlash_deg;
  p.seed = seed;
  p.variants = methods;
  if (c.trajectories == "optimised") {
    p.knee_excitation = optimised_knee;
    p.both_excitation = optimised_both;
  }
  return p;
}

nlohmann::json toJson(const SweepCondition& c) {
  return {{"torque_noise_Nm", c.torque_noise_Nm},
          {"angle_noise_deg", c.angle_noise_deg},
          {"quantisation_deg", c.quantisation_deg},
          {"vibration_level", c.vibration_level},
          {"cylinder_mass_scale", c.cylinder_mass_scale},
          {"encoder_backlash_deg", c.encoder_backlash_deg},
          {"trajectories", c.trajectories}};
}

std::string conditionCsv(const SweepCondition& c) {
  return csvNumber(c.torque_noise_Nm) + "," + csvNumber(c.angle_noise_deg) + "," + csvNumber(c.quantisation_deg) + "," +
         csvNumber(c.vibration_level) + "," + csvNumber(c.cylinder_mass_scale) + "," + csvNumber(c.encoder_backlash_deg) + "," + c.trajectories;
}

namespace {

// The grid's levels, as the APAL leg's and a chain's resolved configurations both record them.
// The backlash axis only when it has a level other than none: a folder started before the axis
// existed (its config.json without the key) resumes, and reads back as no play.
nlohmann::json gridJson(const SweepConfig& c) {
  nlohmann::json g = {{"torque_noise_Nm", c.torque_noise_Nm},
                      {"angle_noise_deg", c.angle_noise_deg},
                      {"quantisation_deg", c.quantisation_deg},
                      {"vibration_level", c.vibration_level},
                      {"cylinder_mass_scale", c.cylinder_mass_scale},
                      {"trajectories", c.trajectories}};
  if (c.encoder_backlash_deg != std::vector<double>{0.0}) g["encoder_backlash_deg"] = c.encoder_backlash_deg;
  return g;
}

nlohmann::json bandRuleJson(const ident::BandRule& b) {
  return {{"motion_fraction", b.motion_fraction}, {"pilot_factor", b.pilot_factor},     {"scan_band_hz", b.scan_band_hz},
          {"inconsistency_ratio", b.inconsistency_ratio}, {"max_factor", b.max_factor}, {"derivative_factor", b.derivative_factor}};
}

}  // namespace

nlohmann::json SweepConfig::chainJson() const {
  nlohmann::json j;
  j["grid"] = gridJson(*this);
  // The model by its file's name and bytes, not its path: a resume from another folder and shards
  // run on other machines match (a file the MJCF includes is not hashed).
  const std::string model_name = model == "leg3" ? model : std::filesystem::path(chain_model_path).filename().string();
  j["sweep"] = {{"seeds", seeds}, {"master_seed", master_seed}, {"methods", methodNames()}, {"cells", numCells()},
                {"model", model_name}, {"model_sha256", core::sha256OfFile(chain_model_path)},
                {"design", "full factorial of the grid lists; torque noise varies fastest; an optimised cell and its default-motion "
                           "twin share seeds; each run: a fit record and a validation record (the default motion of another seed), "
                           "identified as exoid identify --model does, one fit"}};
  if (!chain_selection.empty()) j["sweep"]["selection"] = chain_selection.options();  // a tree's chain (absent: the file whole)
  nlohmann::json simj = {{"duration_s", base.sim.duration_s}, {"dt_s", base.sim.dt_s}};
  const bool optimised = std::count(trajectories.begin(), trajectories.end(), "optimised") > 0;
  if (optimised && chain_design) {
    simj["excitation"] = sim::trajectoryJson(chain_design->series, chain_design->joints);
  }
  j["simulation"] = simj;
  j["signal_options"] = experiments::toJson(defaultArmSignals(base));
  j["band_rule"] = bandRuleJson(base.band_rule);
  j["method_options"] = experiments::toJson(base.methods);
  j["method_options"]["pso_box"] = origin.count("identification.wide_box") ? "wide_box" : "10 x the largest |LS estimate|";
  return j;
}

nlohmann::json SweepConfig::toJson() const {
  if (isChain()) return chainJson();
  nlohmann::json j;
  j["grid"] = gridJson(*this);
  std::vector<std::string> names;
  for (Variant v : methods) names.emplace_back(toString(v));
  j["sweep"] = {{"seeds", seeds}, {"master_seed", master_seed}, {"methods", names}, {"cells", numCells()},
                {"design", "full factorial of the grid lists; torque noise varies fastest; a paper cell and its optimised "
                           "twin share seeds"}};
  nlohmann::json simj = sim::configJson(base.sim);
  for (const char* k : {"seed", "trajectory"}) simj.erase(k);  // set per job / per record
  // Designed identification records change every result: their coefficients are part of the config.
  const bool optimised = std::count(trajectories.begin(), trajectories.end(), "optimised") > 0;
  if (optimised && optimised_knee) simj["excitation_knee"] = sim::trajectoryJson(*optimised_knee, kLegJoints);
  if (optimised && optimised_both) simj["excitation_both"] = sim::trajectoryJson(*optimised_both, kLegJoints);
  j["simulation"] = simj;
  j["signal_options"] = experiments::toJson(base.signals);
  j["band_rule"] = bandRuleJson(base.band_rule);  // the 'default' arm's
  if (base.default_base_terms) j["default_base_terms"] = ident::toString(*base.default_base_terms);
  j["method_options"] = experiments::toJson(base.methods);
  return j;
}

namespace {

toml::table parseTomlFile(const std::string& path) {
  try {
    return toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw SweepConfigError(at(path, e.source()) + ": " + std::string(e.description()));
  }
}

void readSweepKey(Reader& r, const std::string& full, const toml::node& v) {
  SweepConfig& c = r.c;
  if (full == "sweep.seeds") {
    const std::int64_t n = r.integer(v, full);
    if (n < 1 || n > 1000000) throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): must be in [1, 1e6], got " + core::toText(n));
    c.seeds = static_cast<int>(n);
  } else if (full == "sweep.master_seed") {
    const std::int64_t n = r.integer(v, full);
    if (n < 0) throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): must be >= 0");
    c.master_seed = static_cast<std::uint64_t>(n);
  } else if (full == "sweep.methods") {
    r.method_names = r.strings(v, full);
  } else if (full == "sweep.model") {
    const std::optional<std::string> m = v.value<std::string>();
    if (!m || !v.is_string()) throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): expected a model: \"apal\", \"leg3\" or an MJCF file");
    c.origin[full] = r.loc(v);
    const std::filesystem::path fp(*m);
    // A file relative to the config file's folder (as the excitation files); the built-in names as they are.
    const bool builtin = *m == "apal" || *m == "leg3" || m->empty();
    r.model = builtin || fp.is_absolute() ? *m : (std::filesystem::path(r.file).parent_path() / fp).string();
  } else if (full == "sweep.base" || full == "sweep.tip") {
    const std::optional<std::string> link = v.value<std::string>();
    if (!link || !v.is_string() || link->empty()) throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): expected a link of the URDF");
    (full == "sweep.base" ? c.chain_selection.base : c.chain_selection.tip) = *link;
    c.origin[full] = r.loc(v);
  } else if (full == "sweep.lock") {
    for (const std::string& l : r.strings(v, full)) {
      try {
        c.chain_selection.addLock(l);
      } catch (const std::invalid_argument& e) {
        throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): " + e.what());
      }
    }
    c.origin[full] = r.loc(v);
  }
}

void readGridKey(Reader& r, const std::string& full, const toml::node& v) {
  SweepConfig& c = r.c;
  if (full == "grid.torque_noise_Nm") {
    c.torque_noise_Nm = r.numbers(v, full);
  } else if (full == "grid.angle_noise_deg") {
    c.angle_noise_deg = r.numbers(v, full);
  } else if (full == "grid.quantisation_deg") {
    c.quantisation_deg = r.numbers(v, full);
  } else if (full == "grid.vibration_level") {
    c.vibration_level = r.numbers(v, full);
  } else if (full == "grid.cylinder_mass_scale") {
    c.cylinder_mass_scale = r.numbers(v, full);
  } else if (full == "grid.encoder_backlash_deg") {
    c.encoder_backlash_deg = r.numbers(v, full);
  } else if (full == "grid.trajectories") {
    c.trajectories = r.strings(v, full);
  }
}

// A design file of `exoid excite`, relative to the config file's folder unless absolute.
core::FourierSeries readExcitationKey(const Reader& r, const std::string& full, const toml::node& v) {
  const std::optional<std::string> file = v.value<std::string>();
  if (!file) throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): expected a file name (string)");
  const std::filesystem::path fp(*file);
  const std::string resolved = fp.is_absolute() ? *file : (std::filesystem::path(r.file).parent_path() / fp).string();
  try {
    return readExcitationFile(resolved, kLegJoints).series;
  } catch (const std::invalid_argument& e) {
    throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): " + e.what());
  }
}

void readSimulationKey(Reader& r, const std::string& full, const toml::node& v) {
  SweepConfig& c = r.c;
  if (full == "simulation.duration_s") {
    c.base.sim.duration_s = r.number(v, full);
    if (!(c.base.sim.duration_s > 0)) throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): must be > 0");
  } else if (full == "simulation.ramp_s") {
    c.base.sim.ramp_s = r.number(v, full);
  } else if (full == "simulation.dt_s") {
    c.base.sim.dt_s = r.number(v, full);
  } else if (full == "simulation.feedforward") {
    c.base.sim.feedforward = r.boolean(v, full);
  } else if (full == "simulation.excitation_knee") {
    c.optimised_knee = readExcitationKey(r, full, v);
  } else if (full == "simulation.excitation_both") {
    c.optimised_both = readExcitationKey(r, full, v);
  } else if (full == "simulation.excitation") {
    const std::optional<std::string> file = v.value<std::string>();
    if (!file) throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): expected a file name (string)");
    c.origin[full] = r.loc(v);
    const std::filesystem::path fp(*file);
    const std::string resolved = fp.is_absolute() ? *file : (std::filesystem::path(r.file).parent_path() / fp).string();
    try {
      c.chain_design = readExcitationFile(resolved);
    } catch (const std::exception& e) {
      throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): " + e.what());
    }
  }
}

void readIdentificationKey(Reader& r, const std::string& full, const toml::node& v) {
  SweepConfig& c = r.c;
  if (full == "identification.pso_iterations") {
    const std::int64_t n = r.integer(v, full);
    if (n < 1) throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): must be >= 1");
    c.base.methods.rls_pso.pso.max_iterations = static_cast<long>(n);
  } else if (full == "identification.swarm") {
    const std::int64_t n = r.integer(v, full);
    if (n < 2) throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): must be >= 2");
    c.base.methods.rls_pso.pso.swarm_size = static_cast<int>(n);
  } else if (full == "identification.pso_tolerance") {
    c.base.methods.rls_pso.pso.cost_tolerance = r.number(v, full);
  } else if (full == "identification.optimality_gap") {
    c.base.methods.report_optimality_gap = r.boolean(v, full);
  } else if (full == "identification.wide_box") {
    c.base.methods.wide_box_half_width = r.number(v, full);
  } else if (full == "identification.cutoff_hz") {
    c.base.signals.cutoff_hz = r.number(v, full);
  } else if (full == "identification.filter") {
    c.base.signals.filter = r.boolean(v, full);
  } else if (full == "identification.base_terms") {
    r.c.origin[full] = r.loc(v);
    const auto text = v.value<std::string>();
    if (!text || !baseTermsChoices().count(*text)) {
      throw SweepConfigError("'" + full + "' (" + r.loc(v) + "): expected \"off\", \"auto\", \"on\" or \"judged\"");
    }
    c.base.default_base_terms = baseTermsChoices().at(*text);
  } else {
    // The band rule's constants (band_*), for the study that chose them (docs/findings.md).
    ident::BandRule& b = c.base.band_rule;
    double* field = full == "identification.band_motion_fraction"       ? &b.motion_fraction
                    : full == "identification.band_pilot_factor"        ? &b.pilot_factor
                    : full == "identification.band_scan_hz"             ? &b.scan_band_hz
                    : full == "identification.band_inconsistency_ratio" ? &b.inconsistency_ratio
                    : full == "identification.band_max_factor"          ? &b.max_factor
                                                                        : &b.derivative_factor;
    *field = r.number(v, full);
  }
}

// A section of the file: its known keys and how to read one ("section.key").
struct SectionReader {
  std::set<std::string> keys;
  void (*read)(Reader&, const std::string&, const toml::node&);
};

const std::map<std::string, SectionReader>& sectionReaders() {
  static const std::map<std::string, SectionReader> kSections = {
      {"sweep", {{"seeds", "master_seed", "methods", "model", "base", "tip", "lock"}, readSweepKey}},
      {"grid",
       {{"torque_noise_Nm", "angle_noise_deg", "quantisation_deg", "vibration_level", "cylinder_mass_scale", "encoder_backlash_deg", "trajectories"},
        readGridKey}},
      {"simulation", {{"duration_s", "ramp_s", "dt_s", "feedforward", "excitation_knee", "excitation_both", "excitation"}, readSimulationKey}},
      {"identification",
       {{"pso_iterations", "swarm", "pso_tolerance", "optimality_gap", "wide_box", "cutoff_hz", "filter", "band_motion_fraction",
         "band_pilot_factor", "band_scan_hz", "band_inconsistency_ratio", "band_max_factor", "band_derivative_factor", "base_terms"},
        readIdentificationKey}}};
  return kSections;
}

// One [section]: unknown sections and keys are refused, naming the known ones.
void readSection(Reader& r, const std::string& s, const toml::node& node) {
  const auto known = sectionReaders().find(s);
  if (known == sectionReaders().end()) {
    throw SweepConfigError("unknown section '" + s + "' (" + at(r.file, node.source()) +
                           "); expected [sweep], [grid], [simulation] or [identification]");
  }
  const toml::table* tab = node.as_table();
  if (!tab) throw SweepConfigError("'" + s + "' (" + at(r.file, node.source()) + "): expected a table [" + s + "]");
  for (const auto& [k, v] : *tab) {
    const std::string key(k.str());
    if (!known->second.keys.count(key)) {
      const std::string list = core::joined(known->second.keys);
      throw SweepConfigError("unknown key '" + s + "." + key + "' (" + at(r.file, v.source()) + "); [" + s + "] keys: " + list);
    }
    known->second.read(r, s + "." + key, v);
  }
}

}  // namespace

SweepConfig loadSweepConfig(const std::string& path, const std::string& model_override) {
  const toml::table t = parseTomlFile(path);
  SweepConfig c;
  Reader r{path, c, std::nullopt, std::nullopt};
  for (const auto& [section, node] : t) readSection(r, std::string(section.str()), node);
  if (!model_override.empty()) {
    c.setModel(model_override, "--model");
  } else if (r.model) {
    c.setModel(*r.model, c.origin["sweep.model"]);
  }
  if (r.method_names) c.setMethods(*r.method_names, c.origin["sweep.methods"]);
  c.validate();
  return c;
}

}  // namespace exoid::experiments

#include "exoid/experiments/protocol/options.hpp"

#include "exoid/core/format.hpp"

#include <filesystem>
#include <cmath>
#include <map>
#include <optional>

namespace exoid::experiments {

ident::SignalOptions defaultIdentifySignals() {
  ident::SignalOptions o;
  o.processing = ident::Processing::kParallel;
  o.differentiation = ident::Differentiation::kCentral4;
  o.base_terms = ident::BaseTerms::kAuto;
  o.cutoff_from_data = true;
  o.derivative_cutoff_from_data = true;
  return o;
}

const CLI::Validator& seedValidator() {
  static const CLI::Validator v(
      [](std::string& text) -> std::string {
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        if (digits) {
          try {
            (void)std::stoull(text);
            return {};
          } catch (const std::out_of_range&) {
          }
        }
        return "expected a seed: an integer from 0 to 18446744073709551615, got '" + text + "'";
      },
      "SEED");
  return v;
}

namespace {
// The whole text as a number (std::stod accepts "3abc" as 3): nullopt when it is not one.
std::optional<double> wholeNumber(const std::string& text) {
  std::size_t used = 0;
  double x = 0.0;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != text.size() || used == 0) return std::nullopt;
  return x;
}
}  // namespace

// "auto" or a number (> 0, or >= 0 when zero_allowed).
static CLI::Validator autoOrNumber(bool zero_allowed) {
  return CLI::Validator(
      [zero_allowed](std::string& text) -> std::string {
        if (text == "auto") return {};
        const std::optional<double> x = wholeNumber(text);
        if (!x || !std::isfinite(*x) || *x < 0.0 || (!zero_allowed && *x == 0.0)) {
          return std::string("expected 'auto' or a number ") + (zero_allowed ? ">= 0" : "> 0") + ", got '" + text + "'";
        }
        return {};
      },
      zero_allowed ? "auto|HZ>=0" : "auto|HZ>0");
}

// An option taking "auto" (from_data = true) or a number (from_data = false, value = it).
static void addAutoOrNumber(CLI::App& app, const std::string& name, bool& from_data, double& value, bool zero_allowed,
                            const std::string& help) {
  app.add_option_function<std::string>(
         name,
         [&from_data, &value](const std::string& v) {
           from_data = v == "auto";
           if (!from_data) value = *wholeNumber(v);
         },
         help)
      ->check(autoOrNumber(zero_allowed))
      ->default_str(from_data ? "auto" : core::formatNumber(value, 6))
      ->group("Signal processing");
}

const CLI::Validator& positiveNumber() {
  static const CLI::Validator v(
      [](std::string& text) -> std::string {
        const std::optional<double> parsed = wholeNumber(text);
        if (!parsed) return "expected a number > 0, got '" + text + "'";
        const double x = *parsed;
        if (!(x > 0.0) || !std::isfinite(x)) return "must be > 0 and finite, got " + text;
        return {};
      },
      "POSITIVE");
  return v;
}

void addSignalOptions(CLI::App& app, ident::SignalOptions& o) {
  static const std::map<std::string, ident::Processing> kProcessing = {{"parallel", ident::Processing::kParallel},
                                                                      {"paper", ident::Processing::kPaper}};
  app.add_option("--processing", o.processing,
                 "parallel: regressor from the states, then the same zero-phase filter on the torque and every column, "
                 "trimmed and decimated (exact on exact data); paper: the paper's signal filtering")
      ->transform(CLI::CheckedTransformer(kProcessing, CLI::ignore_case))
      ->default_str(ident::toString(o.processing))
      ->group("Signal processing");
  app.add_option("--decimation", o.decimation, "Parallel processing: keep every n-th row (0 = auto: fs / (5 cutoff))")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group("Signal processing");
  addAutoOrNumber(app, "--derivative-cutoff-hz", o.derivative_cutoff_from_data, o.derivative_cutoff_hz, true,
                  "Parallel processing: the angles' pre-filter before differentiating, Hz (0 = none), or auto: 5 x the\n"
                  "cutoff in use");
  app.add_option("--base-terms", o.base_terms,
                 "Parallel processing: pedestal-motion terms from the IMU columns base_acc_x, base_acc_z (specific force "
                 "at the hip axis, m/s^2), base_gyro_y (rad/s): off, auto (when the columns are there), on (required) or judged (when the columns are there and "
                 "they predict held-out torque no worse: 5 contiguous blocks, each by least squares on the others)")
      ->transform(CLI::CheckedTransformer(baseTermsChoices(), CLI::ignore_case))
      ->default_str(ident::toString(o.base_terms))
      ->group("Signal processing");
  static const std::map<std::string, ident::Differentiation> kDiff = {
      {"forward", ident::Differentiation::kForward}, {"central", ident::Differentiation::kCentral},
      {"central4", ident::Differentiation::kCentral4}};
  app.add_option("--diff", o.differentiation, "Differentiation of angles: forward (paper), central or central4 (five-point)")
      ->transform(CLI::CheckedTransformer(kDiff, CLI::ignore_case))
      ->default_str(ident::toString(o.differentiation))
      ->group("Signal processing");
  app.add_flag("!--no-filter", o.filter, "Do not low-pass filter (paper: zero-phase 10 Hz)")
      ->group("Signal processing");
  addAutoOrNumber(app, "--cutoff-hz", o.cutoff_from_data, o.cutoff_hz, false,
                  "Zero-phase Butterworth cutoff of one pass, Hz, or auto (parallel processing): chosen from each\n"
                  "record, the motion's bandwidth and the first band where the states predict more than twice the\n"
                  "torque measured (printed with the reason); the paper's processing uses 10 Hz");
  app.add_option("--filter-order", o.filter_order, "Butterworth order of one pass (forward-backward doubles it)")
      ->check(CLI::Range(1, 8))
      ->capture_default_str()
      ->group("Signal processing");
  app.add_flag("!--no-filter-torque", o.filter_torque, "Do not filter the measured torques")
      ->group("Signal processing");
  app.add_option("--edge-trim", o.edge_trim_s,
                 "Seconds dropped at each end after filtering (negative = auto: 3/cutoff, or 2 samples unfiltered)")
      ->capture_default_str()
      ->group("Signal processing");
  app.add_flag("!--differentiate", o.use_recorded_derivatives,
               "Differentiate the angles even when the dataset has qd_*/qdd_* columns")
      ->group("Signal processing");
}

void addMethodOptions(CLI::App& app, ident::MethodOptions& o) {
  auto& pso = o.rls_pso.pso;
  static const std::map<std::string, ident::BoundaryPolicy> kBoundary = {
      {"clamp", ident::BoundaryPolicy::kClamp}, {"reflect", ident::BoundaryPolicy::kReflect}};
  static const std::map<std::string, ident::CostNorm> kNorm = {{"l1", ident::CostNorm::kL1},
                                                              {"l2", ident::CostNorm::kL2}};
  const char* g = "PSO";
  app.add_option("--seed", pso.seed, "Seed of every random draw of PSO")->check(seedValidator())->capture_default_str()->group(g);
  app.add_option("--pso-iterations", pso.max_iterations, "PSO iterations G (paper: 10000)")
      ->check(positiveNumber())->capture_default_str()->group(g);
  app.add_option("--swarm", pso.swarm_size, "PSO particles")->check(CLI::Range(2, 100000))->capture_default_str()->group(g);
  app.add_option("--pso-tolerance", pso.cost_tolerance, "Stop when the best cost < this (paper: 1e-2)")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--w-max", pso.w_max, "Inertia at the first iteration")->capture_default_str()->group(g);
  app.add_option("--w-min", pso.w_min, "Inertia at the last iteration")->capture_default_str()->group(g);
  app.add_option("--c1", pso.c1, "Cognitive weight")->capture_default_str()->group(g);
  app.add_option("--c2", pso.c2, "Social weight")->capture_default_str()->group(g);
  app.add_option("--velocity-fraction", pso.velocity_fraction, "Velocity range as a fraction of the box width")
      ->capture_default_str()->group(g);
  app.add_option("--boundary", pso.boundary, "Out-of-box positions: clamp (paper) or reflect")
      ->transform(CLI::CheckedTransformer(kBoundary, CLI::ignore_case))->default_str("clamp")->group(g);
  app.add_option("--cost", o.rls_pso.cost, "PSO cost: l1 (paper) or l2")
      ->transform(CLI::CheckedTransformer(kNorm, CLI::ignore_case))->default_str("l1")->group(g);
  app.add_option("--wide-box", o.wide_box_half_width, "Half-width of the PSO baseline's box in every parameter")
      ->check(positiveNumber())->capture_default_str()->group(g);
  const char* r = "RLS";
  app.add_option("--rls-forgetting", o.rls_pso.rls.forgetting, "Forgetting factor lambda in (0, 1]")
      ->capture_default_str()->group(r);
  app.add_option("--rls-p0", o.rls_pso.rls.initial_covariance, "Initial covariance P0 = p0 * I")
      ->check(positiveNumber())->capture_default_str()->group(r);
  app.add_option("--burn-in", o.rls_pso.range.burn_in_fraction,
                 "Fraction of RLS updates ignored for the fluctuation range")->capture_default_str()->group(r);
  app.add_option("--box-margin", o.rls_pso.range.margin_fraction,
                 "Widen each side of the RLS box by this fraction of its width")->capture_default_str()->group(r);
  app.add_flag("!--no-optimality-gap", o.report_optimality_gap,
               "Skip the exact L1 optimum (each PSO run's optimality gap)")->group(g);
  app.add_option("--max-condition", o.ls.max_condition,
                 "Condition number of the column-scaled regressor above which an estimate (any method) is not\n"
                 "usable: a relative torque error of 1/this can move it by 100 % (exit code 3)")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            const std::optional<double> x = wholeNumber(text);
            if (!x || !(*x > 1.0) || !std::isfinite(*x)) {
              return "expected a finite number > 1 (a condition number), got '" + text + "'";
            }
            return {};
          },
          "NUMBER > 1"))
      ->capture_default_str()->group("Usability");
}

void addConstantsOptions(CLI::App& app, ConstantsFlags& f) {
  app.add_option("--thigh-length", f.thigh_length_m,
                 "Thigh length Lt in m (else the --profile's [model], else dataset metadata 'thigh_length_m'; required)")
      ->check(positiveNumber())->group("Model");
  app.add_option("--gravity", f.gravity_mps2, "Gravity in m/s^2 (else the --profile's [model], else metadata 'gravity_mps2', else 9.81)")
      ->check(positiveNumber())->group("Model");
}

namespace {
std::optional<double> metadataNumber(const ident::Dataset& d, const std::string& key) {
  const auto v = d.metadata(key);
  if (!v) return std::nullopt;
  try {
    std::size_t used = 0;
    const double x = std::stod(*v, &used);
    if (used == v->size()) return x;
  } catch (const std::exception&) {
  }
  throw std::invalid_argument("dataset metadata '" + key + "' must be a number, got '" + *v + "'");
}
}  // namespace

ident::LegConstants resolveConstants(const ConstantsFlags& f, const ident::Dataset& d, std::string* origin,
                                     std::optional<double> profile_thigh_length_m, std::optional<double> profile_gravity_mps2) {
  ident::LegConstants c;
  std::string how;
  if (f.thigh_length_m) {
    c.thigh_length_m = *f.thigh_length_m;
    how = "thigh length from --thigh-length";
  } else if (profile_thigh_length_m) {
    c.thigh_length_m = *profile_thigh_length_m;
    how = "thigh length from the log profile";
  } else if (auto v = metadataNumber(d, "thigh_length_m")) {
    c.thigh_length_m = *v;
    how = "thigh length from dataset metadata";
  } else {
    throw std::invalid_argument(
        "the thigh length Lt (hip to knee axis, m) is not known: give --thigh-length M, a '# thigh_length_m: M' line "
        "in the log, or [model] thigh_length_m in the --profile (it scales every thigh parameter: there is no default)");
  }
  if (f.gravity_mps2) {
    c.gravity_mps2 = *f.gravity_mps2;
    how += ", gravity from --gravity";
  } else if (profile_gravity_mps2) {
    c.gravity_mps2 = *profile_gravity_mps2;
    how += ", gravity from the log profile";
  } else if (auto v = metadataNumber(d, "gravity_mps2")) {
    c.gravity_mps2 = *v;
    how += ", gravity from dataset metadata";
  } else {
    how += ", gravity default 9.81 m/s^2";
  }
  c.validate();
  if (origin) *origin = how;
  return c;
}

const std::map<std::string, ident::BaseTerms>& baseTermsChoices() {
  static const std::map<std::string, ident::BaseTerms> kChoices = {
      {"off", ident::BaseTerms::kOff}, {"auto", ident::BaseTerms::kAuto}, {"on", ident::BaseTerms::kOn}, {"judged", ident::BaseTerms::kJudged}};
  return kChoices;
}

std::string baseTermsNote(const ident::BaseTermsChoice& c) {
  return "base-motion terms " + c.describe() + " (--base-terms on|off overrides)";
}

std::string sharedBaseTermsNote(const ident::BaseTermsChoice& pooled) {
  return "  the records were judged differently; fitted together they share one choice, base-motion terms " + pooled.describe() +
         " pooled over their " + core::toText(pooled.equations) + " held-out equations";
}

nlohmann::json toJson(const ident::BaseTermsChoice& c) {
  const auto rms = [&c](double v) { return c.folds ? nlohmann::json(v) : nlohmann::json(nullptr); };  // unjudged: no RMS
  return {{"kept", c.use},
          {"held_out_rms_with_Nm", rms(c.held_out_rms_with_Nm)},
          {"held_out_rms_without_Nm", rms(c.held_out_rms_without_Nm)},
          {"folds", c.folds},
          {"samples", c.samples},
          {"reason", c.describe()},
          {"rule", "kept unless they make the torque RMS of contiguous held-out blocks, each predicted by least squares on the "
                   "others, larger (--base-terms on or off overrides)"}};
}

bool usesBaseMotion(const ident::Dataset& d, const ident::SignalOptions& signals) {
  return signals.processing == ident::Processing::kParallel &&
         (signals.base_terms == ident::BaseTerms::kOn || (ident::whenPresent(signals.base_terms) && ident::hasBaseColumns(d)));
}

nlohmann::json toJson(const ident::SignalOptions& o) {
  return {{"processing", ident::toString(o.processing)},
          {"decimation", o.decimation},
          {"derivative_cutoff_hz", o.derivative_cutoff_hz},
          {"base_terms", ident::toString(o.base_terms)},
          {"differentiation", ident::toString(o.differentiation)},
          {"use_recorded_derivatives", o.use_recorded_derivatives},
          {"filter", o.filter ? "butterworth_filtfilt" : "none"},
          {"filter_order", o.filter_order},
          {"cutoff_hz", o.cutoff_hz},
          {"cutoff_from_data", o.cutoff_from_data},
          {"derivative_cutoff_from_data", o.derivative_cutoff_from_data},
          {"filter_torque", o.filter_torque},
          {"edge_trim_s", o.edge_trim_s}};
}

nlohmann::json toJson(const ident::MethodOptions& o) {
  const auto& p = o.rls_pso.pso;
  return {{"pso",
           {{"seed", p.seed}, {"swarm_size", p.swarm_size}, {"max_iterations", p.max_iterations},
            {"cost_tolerance", p.cost_tolerance}, {"w_max", p.w_max}, {"w_min", p.w_min}, {"c1", p.c1},
            {"c2", p.c2}, {"velocity_fraction", p.velocity_fraction},
            {"boundary", ident::toString(p.boundary)}, {"cost", ident::toString(o.rls_pso.cost)},
            {"wide_box_half_width", o.wide_box_half_width}}},
          {"rls",
           {{"forgetting", o.rls_pso.rls.forgetting}, {"initial_covariance", o.rls_pso.rls.initial_covariance},
            {"burn_in_fraction", o.rls_pso.range.burn_in_fraction},
            {"margin_fraction", o.rls_pso.range.margin_fraction}}},
          {"ls", {{"rank_tolerance", o.ls.rank_tolerance}, {"max_condition", o.ls.max_condition}}},
          {"lad", {{"gap_tolerance", o.lad.gap_tolerance}, {"max_iterations", o.lad.max_iterations}}},
          {"report_optimality_gap", o.report_optimality_gap}};
}

void addTreeLock(core::ChainSelection& selection, const std::string& joint_equals_value) {
  try {
    selection.addLock(joint_equals_value);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--lock", e.what());
  }
}

void addChainSelectionOptions(CLI::App& cmd, core::ChainSelection& selection, bool with_lock) {
  cmd.add_option("--base", selection.base,
                 "Robot trees (a humanoid's or an exoskeleton's whole body): the link the chain starts from, held still\n"
                 "(default: the file's root; MJCF: a body, default the world). Moving branches hanging from it are left out")
      ->group("Robot");
  cmd.add_option("--tip", selection.tip,
                 "Robot trees: the link the chain ends at (e.g. a foot); without it a tree is refused with its leaf links")
      ->group("Robot");
  if (!with_lock) return;
  cmd.add_option_function<std::vector<std::string>>(
         "--lock",
         [&selection](const std::vector<std::string>& locks) {
           for (const std::string& l : locks) addTreeLock(selection, l);
         },
         "Robot trees: JOINT=VALUE holds a joint at VALUE (rad; m for a prismatic one); a moving branch off the chain\n"
         "is refused unless locked, and is lumped into its link at that posture. Repeatable")
      ->group("Robot");
}

std::pair<std::string, std::string> parseStage(const std::string& s) {
  const auto eq = s.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == s.size()) {
    throw CLI::ValidationError("--stage", "expected JOINT=FILE (the record's first moving joint, the joints above it locked), got '" + s + "'");
  }
  const std::string file = s.substr(eq + 1);
  if (!std::filesystem::is_regular_file(file)) throw CLI::ValidationError("--stage", "file '" + file + "' does not exist");
  return {s.substr(0, eq), file};
}

bool apalKneeArmature(const std::vector<std::string>& armature) {
  for (const std::string& joint : armature) {
    if (joint != "knee" && joint != "all") {
      throw CLI::ValidationError("--armature", "the APAL leg takes a knee armature (knee or all): Jt absorbs a hip rotor's inertia "
                                               "(it adds to the hip's diagonal alone); got '" + joint + "'");
    }
  }
  return !armature.empty();
}

}  // namespace exoid::experiments

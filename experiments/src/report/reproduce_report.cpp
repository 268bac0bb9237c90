#include "exoid/core/format.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/report/plots.hpp"
#include "exoid/experiments/protocol/reproduce.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"
#include "exoid/experiments/report/stats.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/core/atomic_file.hpp"
#include "exoid/sim/data_dir.hpp"
#include "exoid/sim/sidecar.hpp"

#ifdef EXOID_WITH_RENDER
#include "exoid/render/clip.hpp"
#include "exoid/render/track.hpp"
#endif

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace exoid::experiments {

ProtocolConfig defaultReproduceConfig() {
  ProtocolConfig c;
  c.sim.duration_s = 10.0;
  c.sim.sensors.quantisation_deg = 360.0 / 131072.0;  // 17-bit absolute encoder
  c.sim.sensors.noise_q_deg = 0.005;
  c.sim.sensors.noise_tau_Nm = 0.5;
  c.sim.variant.vibration_level = 1.0;
  c.sim.variant.cylinder_mass_scale = 1.0;
  return c;
}

std::string defaultKneeExcitationPath() { return sim::dataPath("configs/excitation_knee.json"); }
std::string defaultBothExcitationPath() { return sim::dataPath("configs/excitation_both.json"); }

double medianAbs(const Eigen::VectorXd& v) {
  std::vector<double> a(v.data(), v.data() + v.size());
  for (double& x : a) x = std::abs(x);
  return stats::median(std::move(a));
}

namespace {

using ident::kNumParams;

// The paper's numbers (docs/paper.md): RLS boxes, LS and PSO estimates of the knee, validation
// errors. Table 4's RLS-PSO row and all of Table 6 (the hip estimates) are not in the paper's text.
struct PaperRow {
  const char* name;
  double v[5];
};
const PaperRow kPaperKnee[] = {{"RLS box min (Table 3)", {0.79, -0.98, 0.39, 0.01, 0.02}},
                               {"RLS box max (Table 3)", {1.79, 0.18, 0.91, 1.13, 3.15}},
                               {"LS (Table 4)", {1.3859, -0.8267, 0.7019, 0.0943, 0.2907}},
                               {"PSO (Table 4)", {1.2199, -0.4016, 0.5906, 0.3323, 0.1830}}};
const PaperRow kPaperHip[] = {{"RLS box min (Table 5)", {5.38, 2.34, 2.01, 0.10, 0.01}},
                              {"RLS box max (Table 5)", {11.64, 5.20, 4.25, 7.88, 1.70}}};
struct PaperValidation {
  const char* method;
  double knee_mean, knee_std, hip_mean, hip_std;
};
const PaperValidation kPaperValidation[] = {{"ls", 1.0427, 0.9047, 4.9922, 3.7366},
                                            {"pso", 0.5126, 0.4386, 4.3516, 3.3602},
                                            {"rls-pso", 0.1887, 0.2475, 1.2128, 3.100}};

// The paper's numbers for one method, or nullptr (the harness's own arms).
const PaperValidation* paperValidation(const std::string& method) {
  for (const PaperValidation& p : kPaperValidation) {
    if (method == p.method) return &p;
  }
  return nullptr;
}

const VariantScore* find(const ProtocolResult& r, Variant v) {
  for (const VariantScore& s : r.scores) {
    if (s.variant == v) return &s;
  }
  return nullptr;
}

std::string pct(double x) { return fixed(100.0 * x, 2) + " %"; }

void blockTable(std::ostream& md, const ProtocolResult& r, int first, const PaperRow* paper, int paper_rows,
                const char* stage) {
  std::vector<std::string> header{"row"};
  for (int i = first; i < first + 5; ++i) header.emplace_back(ident::paramName(i));
  TextTable t(header);
  auto add = [&](const std::string& name, const Eigen::Ref<const Eigen::VectorXd>& x) {
    std::vector<std::string> row{name};
    for (int i = 0; i < 5; ++i) row.push_back(fmt(x[i], 4));
    t.addRow(row);
  };
  for (int k = 0; k < paper_rows; ++k) add(std::string("paper: ") + paper[k].name, Eigen::Map<const Eigen::VectorXd>(paper[k].v, 5));
  add("truth: rigid links", r.truths.rigid.segment(first, 5));
  add("truth: best fit of this record", r.truths.best_fit.segment(first, 5));
  add("truth: four-bar band min", r.truths.band_min.segment(first, 5));
  add("truth: four-bar band max", r.truths.band_max.segment(first, 5));
  for (const VariantScore& s : r.scores) {
    for (const Stage& st : s.outcome.stages) {
      if (st.name != stage) continue;
      if (st.estimate.box && (s.variant == Variant::kRlsPso)) {
        add("RLS box min (ours)", st.estimate.box->lower);
        add("RLS box max (ours)", st.estimate.box->upper);
      }
    }
  }
  for (const VariantScore& s : r.scores) {
    std::vector<std::string> row{std::string("estimate: ") + toString(s.variant)};
    const std::vector<BoundHit> hits = boxBoundHits(s.outcome);
    for (int i = first; i < first + 5; ++i) {
      const bool on_bound = std::any_of(hits.begin(), hits.end(), [i](const BoundHit& h) { return h.param == i; });
      row.push_back(fmt(s.outcome.x[i], 4) + (on_bound ? " (on bound)" : ""));
    }
    t.addRow(row);
  }
  for (const VariantScore& s : r.scores) {
    std::vector<std::string> row{std::string("rel. error vs best fit: ") + toString(s.variant)};
    for (int i = first; i < first + 5; ++i) row.push_back(pct(s.vs_best_fit.rel[i]));
    t.addRow(row);
  }
  t.printMarkdown(md);
}

void writeSeries(const ProtocolResult& r, const std::string& dir) {
  const ident::LegConstants lc{r.truths.lt_m, r.truths.g_mps2};
  for (int which = 0; which < 2; ++which) {
    const Record& rec = r.records[which == 0 ? 1 : 3];
    const int joint = which == 0 ? 1 : 0;
    core::writeFileAtomically(dir + (which == 0 ? "/series_validation_knee.csv" : "/series_validation_hip.csv"),
                               [&](std::ostream& out) {
      out << "t,measured";
      std::vector<Eigen::MatrixX2d> preds;
      for (const VariantScore& s : r.scores) {
        out << ',' << toString(s.variant);
        preds.push_back(ident::predictTorque(rec.processed, s.outcome.x, lc));
      }
      out << '\n';
      for (Eigen::Index i = 0; i < rec.processed.size(); ++i) {
        out << fmt(rec.processed.t_s[i], 8) << ',' << fmt(rec.processed.tau_Nm(i, joint), 8);
        for (const auto& p : preds) out << ',' << fmt(p(i, joint), 8);
        out << '\n';
      }
    });
  }
  core::writeFileAtomically(dir + "/series_convergence.csv", [&](std::ostream& out) {
    std::vector<std::pair<std::string, const std::vector<double>*>> cols;
    for (const VariantScore& s : r.scores) {
      for (const Stage& st : s.outcome.stages) {
        if (!st.estimate.cost_history.empty()) cols.emplace_back(std::string(toString(s.variant)) + "_" + st.name, &st.estimate.cost_history);
      }
    }
    out << "iteration";
    std::size_t n = 0;
    for (const auto& [name, h] : cols) {
      out << ',' << name;
      n = std::max(n, h->size());
    }
    out << '\n';
    for (std::size_t i = 0; i < n; ++i) {
      out << i;
      for (const auto& [name, h] : cols) out << ',' << (i < h->size() ? fmt((*h)[i], 10) : fmt(h->back(), 10));
      out << '\n';
    }
  });
}

nlohmann::json resultsJson(const ProtocolResult& r) {
  nlohmann::json j;
  j["tool"] = toolJson();
  j["command"] = "reproduce";
  j["seed"] = r.config.seed;
  j["mujoco_version"] = r.records[0].sim.mujoco_version;
  j["simulation"] = sim::configJson(r.config.sim);
  j["signal_options"] = toJson(r.config.signals);
  j["method_options"] = toJson(r.config.methods);
  j["truth"] = {{"rigid", {{"parameters", paramsJson(r.truths.rigid)}}},
                {"best_fit", {{"parameters", paramsJson(r.truths.best_fit)}}},
                {"four_bar_band", {{"min", paramsJson(r.truths.band_min)}, {"max", paramsJson(r.truths.band_max)}}}};
  for (const Record& rec : r.records) {
    const auto& s = rec.sim.stats;
    j["records"].push_back({{"trajectory", rec.trajectory},
                            {"seed", rec.sim.config.seed},
                            {"tracking_rms_deg", {{"hip", s.tracking_hip.rms_deg}, {"knee", s.tracking_knee.rms_deg}}},
                            {"loop_error_max_m", s.loop_error_max_m},
                            {"pedestal_x_max_abs_m", s.base_x_max_abs_m}});
  }
  for (const VariantScore& s : r.scores) {
    nlohmann::json m = toJson(s.outcome, true);
    m["validation"] = {{"knee_on_trajectory_2", toJson(s.knee_validation)}, {"hip_on_trajectory_4", toJson(s.hip_validation)}};
    m["parameter_error"] = {{"rigid", toJson(s.vs_rigid)}, {"best_fit", toJson(s.vs_best_fit)}};
    m["torque_space_error"] = {
        {"best_fit", {{"hip", s.torque_space_vs_best_fit.hip}, {"knee", s.torque_space_vs_best_fit.knee}}},
        {"rigid", {{"hip", s.torque_space_vs_rigid.hip}, {"knee", s.torque_space_vs_rigid.knee}}}};
    j["methods"][toString(s.variant)] = m;
  }
  j["verdict"] = verdict(r);
  // The paper's own validation errors (Figs. 10, 13), for the figures to draw beside ours.
  for (const PaperValidation& p : kPaperValidation) {
    j["paper"]["validation"][p.method] = {{"knee_on_trajectory_2", {{"mean_abs_Nm", p.knee_mean}, {"std_abs_Nm", p.knee_std}}},
                                          {"hip_on_trajectory_4", {{"mean_abs_Nm", p.hip_mean}, {"std_abs_Nm", p.hip_std}}}};
  }
  j["wall_time_s"] = r.wall_time_s;
  return j;
}

#ifdef EXOID_WITH_RENDER
// A still and a short clip of trajectory 3 (both joints swing) with the RLS-PSO (else first)
// method's predicted torque in the overlay. Returns the markdown to embed.
std::string renderMedia(const ProtocolResult& r, const std::string& dir, bool raw_torque) {
  const Record& rec = r.records[2];
  const VariantScore* shown = find(r, Variant::kRlsPso) ? find(r, Variant::kRlsPso) : &r.scores.front();
  render::Track full = render::trackFromSimulation(rec.sim, "trajectory 3 (simulated)");
  // The processed (trimmed) rows placed by time on the record's rows; NaN on the trimmed edges.
  const double dt = full.sampleInterval_s();
  const auto rowOf = [&](Eigen::Index i) {
    return static_cast<std::size_t>(std::llround((rec.processed.t_s[i] - full.t_s.front()) / dt));
  };
  const auto placed = [&](const Eigen::Ref<const Eigen::VectorXd>& processed) {
    std::vector<double> v(full.size(), std::nan(""));
    for (Eigen::Index i = 0; i < processed.size(); ++i) {
      if (rowOf(i) < v.size()) v[rowOf(i)] = processed[i];
    }
    return v;
  };
  const ident::LegConstants lc{r.truths.lt_m, r.truths.g_mps2};
  const Eigen::MatrixX2d pred = ident::predictTorque(rec.processed, shown->outcome.x, lc);
  for (Eigen::Index j = 0; j < 2; ++j) full.joints[static_cast<std::size_t>(j)].tau_pred_Nm = placed(pred.col(j));
  full.prediction_name = toString(shown->variant);
  // Beside the prediction, the torque it was fitted to (filtered, as the methods saw it): the raw
  // record's sensor noise swings far wider than any model's error.
  if (!raw_torque) {
    for (Eigen::Index j = 0; j < 2; ++j) full.joints[static_cast<std::size_t>(j)].tau_Nm = placed(rec.processed.tau_Nm.col(j));
    full.torque_name = "filtered";
  }
  // The clip: the first 3 s after the trimmed edge (where predictions exist).
  render::Track clip = full;
  const std::size_t first = rowOf(0), last = rowOf(rec.processed.size() - 1);
  const std::size_t count = std::min<std::size_t>(std::min(full.size(), last + 1) - first, static_cast<std::size_t>(std::llround(3.0 / dt)));
  auto cut = [&](std::vector<double>& v) {
    if (!v.empty()) v = std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(first), v.begin() + static_cast<std::ptrdiff_t>(first + count));
  };
  for (std::vector<double>* v : clip.series()) cut(*v);
  for (double v : clip.joints.front().tau_Nm) {
    if (!std::isfinite(v)) throw std::logic_error("reproduce clip: a processed torque row is missing inside the clip");
  }
  render::ClipOptions o;
  o.model_path = r.config.sim.model_path;
  render::renderStill(clip, clip.t_s.front() + 0.75, o, dir + "/leg_trajectory3.png");
  render::renderVideo(clip, o, dir + "/leg_trajectory3.mp4");
  return "The simulated leg on trajectory 3 (pedestal, trunk, thigh, shank, cylinder, rod), with the " +
         std::string(raw_torque ? "raw recorded torque" : "processed torque the methods fit (filtered as they saw it)") +
         " and the " + std::string(toString(shown->variant)) + " model's prediction; the clip "
         "[leg_trajectory3.mp4](leg_trajectory3.mp4) shows 3 s:\n\n![leg](leg_trajectory3.png)\n";
}
#endif

}  // namespace

// "yes", or "no: " and the violated conditions' parameter names (ident::implausibilities).
std::string plausibleText(const MethodOutcome& m) {
  if (m.implausible.empty()) return "yes";
  std::string out = "no:";
  for (const std::string& v : m.implausible) out += " " + v.substr(0, v.find(' '));
  return out;
}

namespace {
// One joint's side of the verdict: which method the truth favours and which the paper's yardstick
// favours, RLS-PSO against LS on both, beside the paper's own numbers.
struct JointView {
  bool knee;
  const char* records;  // "trained on trajectory 1, validated on 2"
  const char* name() const { return knee ? "knee" : "hip"; }
  double truth(const VariantScore& s) const { return knee ? s.torque_space_vs_best_fit.knee : s.torque_space_vs_best_fit.hip; }
  double validation(const VariantScore& s) const { return knee ? s.knee_validation.mean_abs : s.hip_validation.mean_abs; }
  double paper(const char* method) const {
    const PaperValidation* p = paperValidation(method);
    return knee ? p->knee_mean : p->hip_mean;
  }
};

const char* lowerOrHigher(double a, double b) { return a < b ? "lower" : a > b ? "higher" : "equal"; }

void jointVerdict(std::ostream& v, const ProtocolResult& r, const JointView& j) {
  const VariantScore* best = &r.scores.front();
  for (const VariantScore& s : r.scores) {
    if (j.truth(s) < j.truth(*best)) best = &s;
  }
  v << "- **" << j.name() << "** (" << j.records << "): closest to the truth " << toString(best->variant) << " ("
    << pct(j.truth(*best)) << ").";
  const VariantScore* ls = find(r, Variant::kLs);
  const VariantScore* rp = find(r, Variant::kRlsPso);
  if (!ls || !rp) return;
  const bool truth_says = j.truth(*rp) < j.truth(*ls), paper_yardstick_says = j.validation(*rp) < j.validation(*ls);
  v << " RLS-PSO vs LS: torque-space error " << pct(j.truth(*rp)) << " vs " << pct(j.truth(*ls)) << " ("
    << lowerOrHigher(j.truth(*rp), j.truth(*ls)) << "); validation |e| " << fixed(j.validation(*rp), 3) << " vs "
    << fixed(j.validation(*ls), 3) << " N m (" << lowerOrHigher(j.validation(*rp), j.validation(*ls)) << "; paper: "
    << fixed(j.paper("rls-pso"), 4) << " vs " << fixed(j.paper("ls"), 4) << " N m). The paper's claim on the " << j.name() << ": "
    << (truth_says ? "holds" : "does not hold") << " against the truth, "
    << (paper_yardstick_says ? "holds" : "does not hold") << " on the paper's own yardstick.\n";
}

// Estimates a search box decided (value on a bound), by method: the box chose them, not the data.
std::string boundHitsText(const ProtocolResult& r) {
  std::string out;
  for (const VariantScore& s : r.scores) {
    const std::vector<BoundHit> hits = boxBoundHits(s.outcome);
    if (hits.empty()) continue;
    out += (out.empty() ? "" : "; ") + std::string(toString(s.variant)) + ": ";
    for (std::size_t k = 0; k < hits.size(); ++k) {
      out += (k ? ", " : "") + std::string(ident::paramName(hits[k].param)) + " = " + fmt(hits[k].value, 4);
    }
  }
  return out;
}
}  // namespace

std::string verdict(const ProtocolResult& r) {
  std::ostringstream v;
  v << "Rule, per joint: a method is closer to the truth when its torque-space error on that joint is lower "
       "(||Y (x - x*)|| / ||Y x*|| of the joint's torque over 4000 fixed states, x* = the best fit; Scores below); the "
       "paper's yardstick, the validation torque error (mean |e| on the other trajectory), is given beside it. "
       "Joints are not summed: each has its own record and its own claim in the paper.\n\n";
  jointVerdict(v, r, {true, "trained on trajectory 1, validated on 2"});
  jointVerdict(v, r, {false, "trained on trajectory 3 after the knee stage, validated on 4"});
  const VariantScore* pso = find(r, Variant::kPso);
  const VariantScore* rp = find(r, Variant::kRlsPso);
  if (pso && rp) {
    const auto gap = [](const VariantScore& s, bool box) {
      double g = 0.0;
      for (const Stage& st : s.outcome.stages) {
        g = std::max(g, (box ? st.estimate.optimality_gap_box_rel : st.estimate.optimality_gap_rel).value_or(0.0));
      }
      return g;
    };
    v << "- Worst L1 optimality gap over the method's own box: PSO " << pct(gap(*pso, true)) << ", RLS-PSO "
      << pct(gap(*rp, true)) << " (unconstrained: " << pct(gap(*pso, false)) << ", " << pct(gap(*rp, false)) << ").\n";
  }
  if (const std::string hits = boundHitsText(r); !hits.empty()) {
    v << "- On their search box's bound (the box chose these values, not the data; `exoid identify` exits 3 on such an "
         "estimate): " << hits << ".\n";
  }
  v << "\nThis is one seed: `exoid sweep` gives confidence intervals over seeds and conditions.";
  return v.str();
}

namespace {

void writeEstimatesCsv(const ProtocolResult& r, const std::string& path) {
  core::writeFileAtomically(path, [&](std::ostream& o) {
    o << "method,parameter,unit,estimate,truth_rigid,truth_best_fit,rel_error_rigid,rel_error_best_fit\n";
    for (const VariantScore& s : r.scores) {
      for (int i = 0; i < kNumParams; ++i) {
        o << toString(s.variant) << ',' << ident::paramName(i) << ',' << ident::paramInfo()[static_cast<std::size_t>(i)].unit << ','
          << fmt(s.outcome.x[i], 10) << ',' << fmt(r.truths.rigid[i], 10) << ',' << fmt(r.truths.best_fit[i], 10) << ','
          << fmt(s.vs_rigid.rel[i], 6) << ',' << fmt(s.vs_best_fit.rel[i], 6) << '\n';
      }
    }
  });
}

// "a -> b" of two percentages.
std::string arrow(double a, double b, int decimals = 2) { return fixed(100.0 * a, decimals) + " -> " + fixed(100.0 * b, decimals); }

// The optimised-excitation arm next to the paper's: same protocol, seed and validation records.
void optimisedArmSection(std::ostream& md, const ProtocolResult& p, const ProtocolResult& o) {
  md << "\n## Optimised excitation arm\n\n"
        "The same protocol, seed, sensors and rig, identified on designed excitations (`exoid excite`: finite Fourier "
        "series minimising the parameters' Cramer-Rao bounds inside the envelope of the paper's trajectories; "
        "`--excitation-knee/--excitation-both`) instead of trajectories 1 and 3; validation stays on the paper's "
        "trajectories 2 and 4. Each arm is scored against its own best fit (the 2-link LS fit of the exact torques of "
        "its identification records) and both against the rigid links. Designed records: ";
  for (const Record& rec : o.records) {
    if (rec.trajectory != 1 && rec.trajectory != 3) continue;
    md << (rec.trajectory == 1 ? "knee-only" : "both joints") << " (tracking RMS hip " << fmt(rec.sim.stats.tracking_hip.rms_deg, 3)
       << " deg, knee " << fmt(rec.sim.stats.tracking_knee.rms_deg, 3) << " deg)" << (rec.trajectory == 1 ? "; " : ".\n\n");
  }
  md << "Paper's trajectories -> designed, this seed (`exoid sweep --config experiments/configs/excitation_vs_paper.toml` "
        "pairs 30 seeds):\n\n";
  TextTable t({"method", "median parameter error vs best fit (%)", "worst (%)", "median vs rigid links (%)",
               "torque-space error, mean of joints (%)", "knee validation RMS (N m)", "hip validation RMS (N m)"});
  for (std::size_t k = 0; k < p.scores.size() && k < o.scores.size(); ++k) {
    const VariantScore &a = p.scores[k], &b = o.scores[k];
    t.addRow({toString(a.variant), arrow(medianAbs(a.vs_best_fit.rel), medianAbs(b.vs_best_fit.rel)),
              arrow(a.vs_best_fit.rel.cwiseAbs().maxCoeff(), b.vs_best_fit.rel.cwiseAbs().maxCoeff(), 1),
              arrow(medianAbs(a.vs_rigid.rel), medianAbs(b.vs_rigid.rel)),
              arrow(0.5 * (a.torque_space_vs_best_fit.hip + a.torque_space_vs_best_fit.knee),
                    0.5 * (b.torque_space_vs_best_fit.hip + b.torque_space_vs_best_fit.knee)),
              fixed(a.knee_validation.rms, 4) + " -> " + fixed(b.knee_validation.rms, 4),
              fixed(a.hip_validation.rms, 4) + " -> " + fixed(b.hip_validation.rms, 4)});
  }
  t.printMarkdown(md);
  md << "\nPer parameter, absolute error vs each arm's best fit (%), paper's trajectories -> designed:\n\n";
  std::vector<std::string> h{"method"};
  for (int i = 0; i < kNumParams; ++i) h.emplace_back(ident::paramName(i));
  TextTable pt(h);
  for (std::size_t k = 0; k < p.scores.size() && k < o.scores.size(); ++k) {
    std::vector<std::string> row{toString(p.scores[k].variant)};
    for (int i = 0; i < kNumParams; ++i) row.push_back(arrow(std::abs(p.scores[k].vs_best_fit.rel[i]), std::abs(o.scores[k].vs_best_fit.rel[i]), 1));
    pt.addRow(row);
  }
  pt.printMarkdown(md);
  md << "\n`estimates_optimised.csv` and results.json `optimised_excitation_arm` hold this arm's numbers.\n";
}

}  // namespace

namespace {

// results.json (with the optimised arm's), estimates*.csv, validation.csv and the plotted series.
void writeDataFiles(const ProtocolResult& r, const ReproduceOutputs& out, const ProtocolResult* optimised) {
  writeJsonFile(out.dir + "/results.json", resultsJson(r));
  writeEstimatesCsv(r, out.dir + "/estimates.csv");
  if (optimised) {
    nlohmann::json j = resultsJson(r);
    j["optimised_excitation_arm"] = resultsJson(*optimised);
    j["optimised_excitation_arm"].erase("tool");
    writeJsonFile(out.dir + "/results.json", j);
    writeEstimatesCsv(*optimised, out.dir + "/estimates_optimised.csv");
  }
  core::writeFileAtomically(out.dir + "/validation.csv", [&](std::ostream& o) {
    o << "method,joint,validation_trajectory,mean_abs_Nm,std_abs_Nm,rms_Nm,max_abs_Nm\n";
    for (const VariantScore& s : r.scores) {
      for (int k = 0; k < 2; ++k) {
        const auto& e = k == 0 ? s.knee_validation : s.hip_validation;
        o << toString(s.variant) << ',' << (k == 0 ? "knee,2," : "hip,4,") << fmt(e.mean_abs, 8) << ',' << fmt(e.std_abs, 8) << ','
          << fmt(e.rms, 8) << ',' << fmt(e.max_abs, 8) << '\n';
      }
    }
  });
  writeSeries(r, out.dir);
}

void setupSection(std::ostream& md, const ProtocolResult& r) {
  const auto& c = r.config;
  md << "## Setup\n\n";
  md << "- Simulated APAL leg (`" << std::filesystem::path(c.sim.model_path).filename().string() << "`): four-bar knee cylinder mass scale " << c.sim.variant.cylinder_mass_scale
     << ", pedestal vibration level " << c.sim.variant.vibration_level << ", PID tracking at 1 kHz"
     << (c.sim.feedforward ? " with feedforward" : "") << ".\n";
  md << "- Sensors: encoder quantisation " << fmt(c.sim.sensors.quantisation_deg, 4) << " deg, noise " << c.sim.sensors.noise_q_deg
     << " deg; torque noise " << c.sim.sensors.noise_tau_Nm << " N m. Records of " << c.sim.duration_s
     << " s, recorded after a " << c.sim.ramp_s << " s start ramp.\n";
  md << "- Signals: " << ident::toString(c.signals.differentiation)
     << " differences; " << (c.signals.filter ? "zero-phase Butterworth order " + core::toText(c.signals.filter_order) + " at " + fmt(c.signals.cutoff_hz) + " Hz" : std::string("no filter"))
     << "; " << c.signals.edgeTrimSamples(1000.0) << " samples trimmed at each end (the paper's arms: ls, rls, pso, "
        "rls-pso, lad, ls-stacked).\n";
  {
    const ident::SignalOptions p = parallelSignals(c.signals);
    md << "- Parallel arms (ls-parallel, idim-iv, ls-base, idim-iv-base): regressor from five-point differences of the angles "
          "after a " << fmt(p.derivative_cutoff_hz) << " Hz pre-filter, then the same zero-phase filter on the torque and every "
          "column, decimated by " << p.decimationFactor(1000.0) << "; *-base with the pedestal IMU's base-motion terms; IDIM-IV's "
          "instruments from the identified model simulated under the records' PID" << (c.sim.feedforward ? " and model feedforward" : "")
       << ", until every step < " << fmt(c.iv.step_tolerance) << " standard errors.\n";
  }
  md << "- PSO: " << c.methods.rls_pso.pso.swarm_size << " particles, G = " << c.methods.rls_pso.pso.max_iterations
     << ", stop at cost < " << c.methods.rls_pso.pso.cost_tolerance << ", w " << c.methods.rls_pso.pso.w_max << " -> "
     << c.methods.rls_pso.pso.w_min << ", c1 = " << c.methods.rls_pso.pso.c1 << ", c2 = " << c.methods.rls_pso.pso.c2
     << ", boundary " << ident::toString(c.methods.rls_pso.pso.boundary) << ", wide box +-" << c.methods.wide_box_half_width
     << "; RLS lambda = " << c.methods.rls_pso.rls.forgetting << ", P0 = " << fmt(c.methods.rls_pso.rls.initial_covariance)
     << ", burn-in " << pct(c.methods.rls_pso.range.burn_in_fraction) << ".\n";
  if (c.knee_excitation || c.both_excitation) {
    md << "- Identification records: " << (c.knee_excitation ? "a designed knee-only excitation" : std::string("trajectory 1"))
       << " (knee), " << (c.both_excitation ? "a designed both-joint excitation" : std::string("trajectory 3"))
       << " (hip) (`exoid excite`, `--excitation-knee/--excitation-both`); the paper's tables below compare with the "
          "paper's own trajectories; validation stays on trajectories 2 and 4.\n";
  }
  md << "- Records: ";
  for (const Record& rec : r.records) {
    md << "trajectory " << rec.trajectory << " (tracking RMS hip " << fmt(rec.sim.stats.tracking_hip.rms_deg, 3) << " deg, knee "
       << fmt(rec.sim.stats.tracking_knee.rms_deg, 3) << " deg)" << (rec.trajectory < 4 ? "; " : ".\n");
  }
  md << "- Truths: *rigid links* = X of the bare thigh and shank+foot of the model; *best fit* = LS of the exact, noise-free,\n"
        "  vibration-free torques at the exact states of records 1 (knee) and 3 (hip): the best the 2-link model can do;\n"
        "  *four-bar band* = X(q2) with cylinder and rod lumped into the links, min/max over the records' knee range.\n"
        "  Errors below are against the best fit unless said otherwise.\n\n";
}

void truthInBoxSection(std::ostream& md, const ProtocolResult& r) {
  md << "\n## Is the truth inside the RLS box?\n\n";
  for (const VariantScore& s : r.scores) {
    if (s.variant != Variant::kRlsPso) continue;
    for (const Stage& st : s.outcome.stages) {
      if (!st.estimate.box) continue;
      md << "- " << st.name << ":";
      for (std::size_t k = 0; k < st.indices.size(); ++k) {
        const int i = st.indices[k];
        const auto kk = static_cast<Eigen::Index>(k);
        const bool in_bf = r.truths.best_fit[i] >= st.estimate.box->lower[kk] && r.truths.best_fit[i] <= st.estimate.box->upper[kk];
        const bool in_rg = r.truths.rigid[i] >= st.estimate.box->lower[kk] && r.truths.rigid[i] <= st.estimate.box->upper[kk];
        md << ' ' << ident::paramName(i) << " best fit " << (in_bf ? "inside" : "**outside") << (in_bf ? "" : "**") << ", rigid "
           << (in_rg ? "inside" : "**outside") << (in_rg ? "" : "**") << ";";
      }
      md << '\n';
    }
  }
}

// The paper's validation errors for one joint, the numbers its claim rests on.
void paperValidationLine(std::ostream& md, const char* joint, int trajectory) {
  md << "Paper's validation error on trajectory " << trajectory << " (mean +- std |e|, N m):";
  for (const auto& p : kPaperValidation) {
    const bool knee = std::string(joint) == "knee";
    md << ' ' << p.method << ' ' << fixed(knee ? p.knee_mean : p.hip_mean, 4) << " +- " << fixed(knee ? p.knee_std : p.hip_std, 4)
       << (&p == &kPaperValidation[2] ? ".\n\n" : ";");
  }
}

void validationSection(std::ostream& md, const ProtocolResult& r) {
  md << "\n## Validation torque error (paper Figs. 10, 13): mean +- std of |error|, N m\n\n";
  TextTable v({"method", "knee (train 1, validate 2)", "paper knee", "hip (train 3, validate 4)", "paper hip", "knee RMS", "hip RMS"});
  for (const VariantScore& s : r.scores) {
    std::string pk = "-", ph = "-";
    if (const PaperValidation* p = paperValidation(toString(s.variant))) {
      pk = fixed(p->knee_mean, 4) + " +- " + fixed(p->knee_std, 4);
      ph = fixed(p->hip_mean, 4) + " +- " + fixed(p->hip_std, 4);
    }
    v.addRow({toString(s.variant), fixed(s.knee_validation.mean_abs, 4) + " +- " + fixed(s.knee_validation.std_abs, 4), pk,
              fixed(s.hip_validation.mean_abs, 4) + " +- " + fixed(s.hip_validation.std_abs, 4), ph, fixed(s.knee_validation.rms, 4),
              fixed(s.hip_validation.rms, 4)});
  }
  v.printMarkdown(md);
}

void scoresSection(std::ostream& md, const ProtocolResult& r) {
  md << "\n## Scores against ground truth\n\n"
        "Torque-space error: ||Y (x - x*)|| / ||Y x*|| per joint on " << ident::kValidationStates
     << " fixed validation states (hip -90..30 deg, knee 0..110 deg, |qd| <= 3 rad/s, |qdd| <= 30 rad/s^2; "
        "`ident::validationStates`), x* = best fit: a parameter error weighed by what it does to the predicted torque. "
        "The norm ||x - x*|| / ||x*|| is dominated by Mxt and Myt and is kept for comparison only. L1 optimality gaps: "
        "against the exact minimum of the paper's cost over the method's own search box, and unconstrained. Physically "
        "plausible: Js > 0, Jt > Js, friction >= 0 (what the parameter definitions imply).\n\n";
  TextTable pe({"method", "torque-space error hip", "knee", "median / worst |param error|", "norm (Mxt-dominated)",
                "L1 gap over its box (knee / hip)", "L1 gap unconstrained", "physically plausible", "time (s)"});
  for (const VariantScore& s : r.scores) {
    Eigen::Index worst = 0;
    s.vs_best_fit.rel.cwiseAbs().maxCoeff(&worst);
    const double med = medianAbs(s.vs_best_fit.rel);
    std::string gaps, box_gaps;
    for (const Stage& st : s.outcome.stages) {
      if (st.estimate.optimality_gap_rel) gaps += (gaps.empty() ? "" : " / ") + pct(*st.estimate.optimality_gap_rel);
      if (st.estimate.optimality_gap_box_rel) box_gaps += (box_gaps.empty() ? "" : " / ") + pct(*st.estimate.optimality_gap_box_rel);
    }
    pe.addRow({toString(s.variant), pct(s.torque_space_vs_best_fit.hip), pct(s.torque_space_vs_best_fit.knee),
               pct(med) + " / " + std::string(ident::paramName(static_cast<int>(worst))) + " " + pct(s.vs_best_fit.rel[worst]),
               pct(s.vs_best_fit.norm_rel), box_gaps.empty() ? "-" : box_gaps, gaps.empty() ? "-" : gaps,
               plausibleText(s.outcome), fmt(s.outcome.wallTime_s(), 3)});
  }
  pe.printMarkdown(md);
}

void crbSection(std::ostream& md, const ProtocolResult& r) {
  md << "\n## Errors in units of each method's Cramer-Rao bound\n\n"
        "(x - x*) / sigma, sigma = the noise-limited std of the parameter for the regressor the method fits, after its "
        "own processing and for its own structure (segmental or stacked; `experiments::noiseStd`), at the records' "
        "torque noise. |z| <= 2-3 means noise-limited; larger means bias (model, processing, vibration). IDIM-IV is "
        "scored against the LS bound of the rows it fits: the least-squares bound, which an instrumental-variable "
        "estimate cannot beat (its own covariance is larger), so its |z| overstates its error in its own units.\n\n";
  std::vector<std::string> zh{"method"};
  for (int i = 0; i < kNumParams; ++i) zh.emplace_back(ident::paramName(i));
  TextTable zt(zh), ct(zh);
  for (const VariantScore& s : r.scores) {
    std::vector<std::string> zrow{toString(s.variant)}, crow{toString(s.variant)};
    for (int i = 0; i < kNumParams; ++i) {
      const double sd = s.crb_std[i];
      zrow.push_back(sd > 0.0 && std::isfinite(sd) ? fixed(s.vs_best_fit.abs[i] / sd, 1) : "-");
      crow.push_back(fmt(sd, 3));
    }
    zt.addRow(zrow);
    ct.addRow(crow);
  }
  zt.printMarkdown(md);
  md << "\nA nominal 95 % interval, x -+ 1.96 sigma, held the truth where |z| <= 1.96. This is one seed: how often it "
        "holds over seeds (the coverage, with its binomial interval and the mean error in sigmas) is in every sweep's "
        "summary (`exoid sweep`; docs/findings.md, section 4.6).\n";
  md << "\nThe bounds themselves (sigma, SI units):\n\n";
  ct.printMarkdown(md);
  // The errors the LS arms report (identify's rule stage by stage): these include model error.
  TextTable rt(zh);
  for (const VariantScore& s : r.scores) {
    if (!s.outcome.segmental_errors) continue;
    std::vector<std::string> row{toString(s.variant)};
    for (int i = 0; i < kNumParams; ++i) {
      const double se = s.outcome.segmental_errors->reported[i];
      row.push_back(se > 0.0 && std::isfinite(se) ? fixed(s.vs_best_fit.abs[i] / se, 1) : "-");
    }
    rt.addRow(row);
  }
  md << "\nThe same errors in units of the standard errors each LS arm reports (`identify --knee-data --both-data`: "
        "Newey-West or the block jackknife, the larger, stage by stage with what the knee stage carries into the hip's; "
        "they see model error where the bound sees noise only):\n\n";
  rt.printMarkdown(md);
}

void figuresSection(std::ostream& md) {
  {
    md << "\n## Figures\n\n";
    md << "Measured vs identified torque on the validation trajectories (paper Figs. 9, 12):\n\n"
          "![knee validation](fig_validation_knee.png)\n\n![hip validation](fig_validation_hip.png)\n\n";
    md << "Best-cost convergence of PSO and RLS-PSO (paper Figs. 8, 11):\n\n![convergence](fig_convergence.png)\n\n";
    md << "Validation error per method (paper Figs. 10, 13):\n\n![validation errors](fig_validation_errors.png)\n\n";
    md << "Relative parameter error per method against the best-fit truth:\n\n![parameter errors](fig_parameter_errors.png)\n";
  }
}

}  // namespace

void writeReproduceOutputs(const ProtocolResult& r, const ReproduceOutputs& out, const ProtocolResult* optimised) {
  std::filesystem::create_directories(out.dir);
  writeDataFiles(r, out, optimised);
  if (out.plots) runPlotScript("reproduce_plots.py", {out.dir});
  std::string media;
#ifdef EXOID_WITH_RENDER
  if (out.media) media = renderMedia(r, out.dir, out.clip_raw_torque);
#endif

  std::ostringstream md;
  const auto& c = r.config;
  md << "# exoid reproduce: the RLS-PSO paper against ground truth\n\n";
  md << "exoid " << toolJson()["version"].get<std::string>() << " (git " << toolJson()["revision"].get<std::string>()
     << "), MuJoCo " << r.records[0].sim.mujoco_version << ", Eigen " << EIGEN_WORLD_VERSION << '.' << EIGEN_MAJOR_VERSION << '.'
     << EIGEN_MINOR_VERSION << "; seed " << c.seed << "; protocol " << fmt(r.wall_time_s, 3) << " s.\n\n";
  md << "## Verdict\n\n" << verdict(r) << "\n\n";
  setupSection(md, r);
  md << "## Knee parameters (paper Tables 3-4; identified on trajectory 1)\n\n";
  paperValidationLine(md, "knee", 2);
  blockTable(md, r, ident::kShankFirst, kPaperKnee, 4, "knee");
  md << "\nThe paper's Table 4 gives no RLS-PSO row in its text. \"(on bound)\": the value sits on its search box's bound.\n";
  md << "\n## Hip parameters (paper Tables 5-6; identified on trajectory 3)\n\n";
  paperValidationLine(md, "hip", 4);
  blockTable(md, r, ident::kThighFirst, kPaperHip, 2, "hip");
  md << "\nThe paper's Table 6 (its LS, PSO and RLS-PSO estimates of X(1:5)) is printed as an image whose values are not in "
        "the text; only Table 5's box is given here, not guessed values.\n";
  truthInBoxSection(md, r);
  validationSection(md, r);
  scoresSection(md, r);
  crbSection(md, r);
  if (optimised) optimisedArmSection(md, r, *optimised);
  if (out.plots) figuresSection(md);
  if (!media.empty()) md << "\n## The leg\n\n" << media;
  md << "\n## Files\n\n`results.json` (everything, with the PSO histories), `estimates.csv`, `validation.csv`, "
        "`series_*.csv` (the plotted series).\n";
  core::writeFileAtomically(out.dir + "/report.md", [&](std::ostream& o) { o << md.str(); });
}

}  // namespace exoid::experiments

#include "exoid/experiments/protocol/excitation_design.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"
#include "exoid/experiments/report/plots.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/sim/data_dir.hpp"
#include "exoid/sim/model.hpp"
#include "exoid/sim/trajectory_json.hpp"
#include "exoid/sim/truth.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>

namespace exoid::experiments {

namespace {

Eigen::VectorXd limitOr(const std::vector<double>& given, const Eigen::VectorXd& model, double scale, const char* flag) {
  if (given.empty()) return model;
  if (static_cast<Eigen::Index>(given.size()) != model.size()) {
    throw CLI::ValidationError(flag, "expected one value per joint (" + core::toText(model.size()) + ")");
  }
  Eigen::VectorXd v(model.size());
  for (Eigen::Index j = 0; j < v.size(); ++j) v[j] = given[static_cast<std::size_t>(j)] * scale;
  return v;
}

// What a design is made for: the robot in the parameters it identifies, their nominal values and
// the limits; the APAL leg's constants when its design is compared with the paper's.
struct DesignTarget {
  std::string name, path;
  std::vector<std::string> joints;
  ident::Robot robot;
  Eigen::VectorXd nominal;
  ident::ExcitationLimits limits;
  std::string limits_source;
  std::optional<ident::LegConstants> apal;
};

// The APAL leg in X: the paper's envelope, or the rig's range, speed and effort from its URDF
// (acceleration then bounded through the effort by the nominal model, not separately).
DesignTarget apalTarget(const ExciteRequest& r, const std::string& path) {
  if (!r.armature.empty()) {
    throw CLI::ValidationError("--armature", "designs a chain's armature parameters; the APAL leg's design is in the paper's X (its "
                                             "knee armature's column is Js's on a knee-only record)");
  }
  if (!r.urdf.empty() && r.limits != "urdf") throw CLI::ValidationError("--urdf", "gives the limits of --limits urdf; give that too");
  const sim::Truth truth = sim::truthFromModel(path);
  DesignTarget t{"APAL leg", path, kLegJoints, {}, {}, {}, {}, constantsOf(truth)};
  t.robot = ident::twoLinkLeg(*t.apal);
  t.nominal = toParamVector(truth.x);
  t.limits = paperEnvelope(*t.apal, t.nominal);
  t.limits_source = "envelope of the paper's trajectories 1-4 on the nominal model";
  if (r.limits == "urdf") {
    const std::string urdf = r.urdf.empty() ? sim::dataPath("models/apal_leg.urdf") : r.urdf;
    const sim::UrdfJointLimits u = sim::urdfJointLimits(urdf);
    for (int j = 0; j < 2; ++j) {
      const auto J = static_cast<std::size_t>(j);
      t.limits.q_min_rad[j] = u.lower_rad[J];
      t.limits.q_max_rad[j] = u.upper_rad[J];
      t.limits.qd_max_radps[j] = u.velocity_radps[J];
      t.limits.tau_max_Nm[j] = u.effort_Nm[J];
      t.limits.qdd_max_radps2[j] = 1e6;
    }
    t.limits_source = "the URDF's joint limits (" + urdf + "), acceleration bounded by the effort";
  }
  return t;
}

// A chain in its base parameters, under its model file's joint limits.
DesignTarget chainTarget(const ExciteRequest& r) {
  if (r.limits != "paper" || !r.urdf.empty()) {
    throw CLI::ValidationError(!r.urdf.empty() ? "--urdf" : "--limits", "chooses the APAL leg's limits; '" + r.model +
                                                                            "' is designed under its model file's own limits");
  }
  const LoadedChain loaded = loadChain(r.model, r.armature, r.selection);
  DesignTarget t{loaded.chain.name, loaded.path, loaded.model.jointNames(), loaded.robot, loaded.base.combination * loaded.phi, {},
                 "the model's joint limits (speed 3 rad/s, acceleration 30 rad/s^2 where it gives none)", std::nullopt};
  const int dof = loaded.model.dof();
  ident::ExcitationLimits& lim = t.limits;
  lim.q_min_rad.resize(dof);
  lim.q_max_rad.resize(dof);
  lim.qd_max_radps.resize(dof);
  lim.qdd_max_radps2 = Eigen::VectorXd::Constant(dof, 30.0);
  lim.tau_max_Nm.resize(dof);
  for (int j = 0; j < dof; ++j) {
    const sim::ChainLinkBody& l = loaded.chain.links[static_cast<std::size_t>(j)];
    lim.q_min_rad[j] = l.q_min_rad;
    lim.q_max_rad[j] = l.q_max_rad;
    lim.qd_max_radps[j] = std::isfinite(l.qd_max_radps) ? l.qd_max_radps : 3.0;
    lim.tau_max_Nm[j] = l.tau_max_Nm;
  }
  return t;
}

// The joints above --first-moving held where --held-at-deg says (or each one's default).
void holdJoints(const ExciteRequest& r, const DesignTarget& t, ident::ExcitationOptions& o) {
  if (r.first_moving.empty()) {
    if (!r.held_at_deg.empty()) throw CLI::ValidationError("--held-at-deg", "holds the joints above --first-moving; give it");
    return;
  }
  const auto it = std::find(t.joints.begin(), t.joints.end(), r.first_moving);
  if (it == t.joints.end()) {
    throw CLI::ValidationError("--first-moving", "'" + r.first_moving + "' is not a joint of " + t.name + " (" + core::joined(t.joints) + ")");
  }
  o.locked_joints = static_cast<int>(it - t.joints.begin());
  if (o.locked_joints == 0) {
    throw CLI::ValidationError("--first-moving", r.first_moving + " is " + t.name + "'s first joint: every joint moves (leave the option out)");
  }
  if (!r.held_at_deg.empty() && static_cast<int>(r.held_at_deg.size()) != o.locked_joints) {
    throw CLI::ValidationError("--held-at-deg", "expected one angle per held joint (" + core::toText(o.locked_joints) + ")");
  }
  o.locked_at_rad.resize(o.locked_joints);
  for (int j = 0; j < o.locked_joints; ++j) {
    const double lo = t.limits.q_min_rad[j], hi = t.limits.q_max_rad[j];
    double at = 0.0;
    if (!r.held_at_deg.empty()) {
      at = r.held_at_deg[static_cast<std::size_t>(j)] * M_PI / 180.0;
    } else if (t.apal) {
      at = -10.0 * M_PI / 180.0;  // the paper's knee-only record holds its hip there
    } else if (std::isfinite(lo) && std::isfinite(hi) && !(lo + 0.1 * (hi - lo) < 0.0 && 0.0 < hi - 0.1 * (hi - lo))) {
      at = 0.5 * (lo + hi);  // 0 would sit on (or next to) a stop
    }
    if (at < lo || at > hi) {
      throw CLI::ValidationError("--held-at-deg", t.joints[static_cast<std::size_t>(j)] + " held at " + fmt(at * 180.0 / M_PI, 4) +
                                                      " deg is outside its range [" + fmt(lo * 180.0 / M_PI, 4) + ", " + fmt(hi * 180.0 / M_PI, 4) + "] deg");
    }
    o.locked_at_rad[j] = at;
  }
}

// The design's Cramer-Rao stds on the footing, and the APAL leg's comparison with the paper's
// trajectory (1 for a knee-only design, 3 for both joints) and with the floor.
struct Footing {
  std::vector<int> indices;  ///< the parameters the design identifies
  /// What the moving joints' equations touch but cannot separate from those with the joints held.
  std::vector<std::string> not_separable;
  Eigen::VectorXd crb;
  int paper_id = 0;  ///< the APAL leg only
  core::FourierSeries paper;
  ident::ExcitationScore paper_score;
  Eigen::VectorXd crb_paper, floor;
};

Footing footingOf(const ExciteRequest& r, const DesignTarget& t, const ident::ExcitationDesign& d, const ident::ExcitationOptions& o) {
  Footing f;
  f.indices = ident::excitationParameters(t.robot, o.locked_joints, o.locked_at_rad);
  for (int p = 0; p < t.robot.parameters(); ++p) {
    const bool touched = std::any_of(t.robot.joint_columns.begin() + o.locked_joints, t.robot.joint_columns.end(),
                                     [p](const std::vector<int>& columns) { return std::count(columns.begin(), columns.end(), p) > 0; });
    if (touched && std::count(f.indices.begin(), f.indices.end(), p) == 0) f.not_separable.push_back(t.robot.names()[static_cast<std::size_t>(p)]);
  }
  f.crb = excitationCrb(d.trajectory, t.robot, r.duration_s, r.rate_hz, r.sigma_Nm);
  if (!t.apal) return f;
  const bool hip_held = o.locked_joints > 0;
  f.paper_id = hip_held ? 1 : 3;
  f.paper = sim::paperTrajectory(f.paper_id);
  f.paper_score = ident::scoreExcitation(t.robot, f.paper, t.nominal, t.limits, 1000);
  f.crb_paper = excitationCrb(f.paper, t.robot, r.duration_s, r.rate_hz, r.sigma_Nm);
  f.floor = ident::crbFloor(t.limits, *t.apal, hip_held, hip_held ? o.locked_at_rad[0] : 0.0, r.duration_s * r.rate_hz, r.sigma_Nm);
  return f;
}

nlohmann::json named(const DesignTarget& t, const std::vector<int>& indices, const Eigen::VectorXd& v) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t k = 0; k < indices.size(); ++k) j[t.robot.names()[static_cast<std::size_t>(indices[k])]] = v[static_cast<Eigen::Index>(k)];
  return j;
}

nlohmann::json designJson(const ExciteRequest& r, const DesignTarget& t, const ident::ExcitationOptions& o, const ident::ExcitationDesign& d,
                          const Footing& f) {
  nlohmann::json j;
  j["tool"] = toolJson();
  j["command"] = "excite";
  j["seed"] = o.seed;
  j["model"] = {{"name", t.name}, {"path", t.path}};
  const std::vector<std::string> held(t.joints.begin(), t.joints.begin() + o.locked_joints);
  j["options"] = {{"criterion", ident::toString(o.criterion)}, {"harmonics", o.harmonics}, {"f0_hz", o.f0_hz},
                  {"held_joints", held},  {"held_at_rad", std::vector<double>(o.locked_at_rad.data(), o.locked_at_rad.data() + o.locked_at_rad.size())},
                  {"restarts", o.restarts}, {"max_evaluations", o.max_evaluations}, {"samples", o.samples}};
  j["criterion"] = std::string(o.criterion == ident::ExcitationCriterion::kCrb
                                   ? "sum of log Cramer-Rao standard deviations of the LS estimates (D-optimality plus a penalty on "
                                     "their correlations), minimised"
                                   : "log condition number of the column-scaled regressor, minimised") +
                   " over one period (the moving joints' equations, over the parameters they determine)";
  j["limits"] = limitsJson(t.limits, t.limits_source + (r.overrides.empty() ? "" : ", with overrides"));
  j["trajectory"] = sim::trajectoryJson(d.trajectory, t.joints);
  j["score"] = scoreJson(d);
  nlohmann::json& c = j["comparison"];
  c["footing"] = {{"duration_s", r.duration_s}, {"rate_hz", r.rate_hz}, {"sigma_Nm", r.sigma_Nm},
                  {"note", "LS on raw torques, white noise on each joint"}};
  c["crb_std"] = named(t, f.indices, f.crb);
  c["not_separable"] = f.not_separable;
  if (!t.apal) return j;
  c["paper_trajectory"] = f.paper_id;
  c["paper_condition_number"] = f.paper_score.condition_number;
  c["paper_crb_std"] = named(t, f.indices, f.crb_paper);
  c["crb_floor_std"] = named(t, f.indices, f.floor);
  c["crb_floor_note"] = "no trajectory inside the limits can do better (single-parameter Cauchy-Schwarz bound from the joint ranges, |qd| "
                        "and |qdd| limits)";
  return j;
}

// The design (and the paper's trajectory) over one period of the design: angle, speed,
// acceleration and nominal torque per joint, what the figure plots.
void writeSeriesCsv(const std::string& path, const DesignTarget& t, const core::FourierSeries& design, const Footing& f) {
  std::vector<const core::FourierSeries*> series{&design};
  if (t.apal) series.push_back(&f.paper);
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "t_s";
    for (std::size_t s = 0; s < series.size(); ++s) {
      for (const char* q : {"q", "qd", "qdd", "tau"}) {
        for (const std::string& joint : t.joints) out << ',' << (s == 0 ? "design" : "paper") << '_' << q << '_' << joint;
      }
    }
    out << '\n';
    ident::RobotWorkspace work;
    const int n = 1000;
    for (int i = 0; i <= n; ++i) {
      const double time_s = design.period_s() * i / n;
      out << fmt(time_s, 8);
      for (const core::FourierSeries* s : series) {
        Eigen::VectorXd q, qd, qdd;
        s->at(time_s, q, qd, qdd);
        const Eigen::VectorXd tau = ident::robotTorque(t.robot, q, qd, qdd, t.nominal, work);
        for (const Eigen::VectorXd* v : std::initializer_list<const Eigen::VectorXd*>{&q, &qd, &qdd, &tau}) {
          for (Eigen::Index j = 0; j < v->size(); ++j) out << ',' << fmt((*v)[j], 10);
        }
      }
      out << '\n';
    }
  });
}

void printDesign(const ExciteRequest& r, const DesignTarget& t, const ident::ExcitationOptions& o, const ident::ExcitationDesign& d,
                 const Footing& f, const std::string& figure) {
  std::string held = "every joint moving";
  if (o.locked_joints > 0) {
    held.clear();
    for (int j = 0; j < o.locked_joints; ++j) {
      held += (j ? ", " : "") + t.joints[static_cast<std::size_t>(j)] + " held at " + fmt(o.locked_at_rad[j] * 180.0 / M_PI, 4) + " deg";
    }
  }
  std::cout << "excitation design of " << t.name << " (" << held << "; N = " << o.harmonics << ", f0 = " << fmt(o.f0_hz) << " Hz, seed "
            << o.seed << "): " << d.evaluations << " evaluations, " << d.feasible_restarts << "/" << o.restarts << " restarts feasible, "
            << fmt(d.wall_time_s, 3) << " s\n"
            << "criterion " << ident::toString(o.criterion) << "; condition number " << fmt(d.score.condition_number, 4)
            << (t.apal ? " (paper's trajectory " + core::toText(f.paper_id) + ": " + fmt(f.paper_score.condition_number, 4) + ")" : std::string())
            << "; " << (d.score.worst_violation == 0.0 ? std::string("inside every limit") : "beyond " + d.score.worst_violation_name) << "\n";
  std::vector<std::string> header{"param", "CRB std, design"};
  if (t.apal) header.insert(header.end(), {"CRB std, paper's " + core::toText(f.paper_id), "gain", "floor", "max gain"});
  TextTable table(header);
  for (std::size_t i = 0; i < f.indices.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    std::vector<std::string> row{t.robot.names()[static_cast<std::size_t>(f.indices[i])], fmt(f.crb[k], 3)};
    if (t.apal) {
      row.insert(row.end(), {fmt(f.crb_paper[k], 3), fmt(f.crb_paper[k] / f.crb[k], 3), fmt(f.floor[k], 3), fmt(f.crb_paper[k] / f.floor[k], 3)});
    }
    table.addRow(row);
  }
  table.print(std::cout);
  if (!f.not_separable.empty()) {
    std::cout << wrapped("not separable from the parameters above while " + held + " (their columns are combinations of those): " +
                         core::joined(f.not_separable) + "; a record with those joints moving identifies them")
              << "\n";
  }
  std::cout << "(" << fmt(r.duration_s) << " s at " << fmt(r.rate_hz) << " Hz, " << fmt(r.sigma_Nm) << " N m white torque noise; LS on raw torques"
            << (t.apal ? ". gain = paper's std / design's; floor = the least std any\ntrajectory inside these limits can reach, max gain = "
                         "paper's std / floor"
                       : "")
            << ")\n";
  if (t.apal && t.limits.qdd_max_radps2.maxCoeff() >= 1e5) {
    std::cout << "(no acceleration limit here: the floors of the inertial and coupled gravity columns are not informative)\n";
  }
  std::cout << "wrote " << r.out << (figure.empty() ? "" : " and " + figure) << "\n";
}

}  // namespace

void LimitOverrides::applyTo(ident::ExcitationLimits& lim) const {
  const double deg = M_PI / 180.0;
  lim.q_min_rad = limitOr(q_min_deg, lim.q_min_rad, deg, "--q-min-deg");
  lim.q_max_rad = limitOr(q_max_deg, lim.q_max_rad, deg, "--q-max-deg");
  lim.qd_max_radps = limitOr(qd_max, lim.qd_max_radps, 1.0, "--qd-max");
  lim.qdd_max_radps2 = limitOr(qdd_max, lim.qdd_max_radps2, 1.0, "--qdd-max");
  lim.tau_max_Nm = limitOr(tau_max, lim.tau_max_Nm, 1.0, "--tau-max");
}

void excite(const ExciteRequest& r) {
  if (r.limits != "paper" && r.limits != "urdf") throw CLI::ValidationError("--limits", "expected paper or urdf, got '" + r.limits + "'");
  const std::string path = sim::modelPathFor(r.model);
  DesignTarget t = isApalLeg(path, r.selection) ? apalTarget(r, path) : chainTarget(r);
  r.overrides.applyTo(t.limits);
  t.limits.validate(t.joints);
  ident::ExcitationOptions o = r.options;
  holdJoints(r, t, o);
  o.validate();
  core::prepareOutputFile(r.out);  // checked before the design's seconds of work
  const ident::ExcitationDesign d = ident::designExcitation(o, t.robot, t.nominal, t.limits);
  const Footing f = footingOf(r, t, d, o);
  writeJsonFile(r.out, designJson(r, t, o, d, f));
  std::string figure;
  if (r.plot) {
    const std::string stem = r.out.size() > 5 && r.out.substr(r.out.size() - 5) == ".json" ? r.out.substr(0, r.out.size() - 5) : r.out;
    writeSeriesCsv(stem + "_series.csv", t, d.trajectory, f);
    figure = stem + ".png";
    runPlotScript("excitation_plot.py", {stem + "_series.csv", r.out, figure});
  }
  printDesign(r, t, o, d, f, figure);
}

}  // namespace exoid::experiments

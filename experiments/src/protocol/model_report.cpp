#include "exoid/experiments/protocol/model_report.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/experiments/protocol/identification.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/sim/model.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <nlohmann/json.hpp>

#include <ostream>

namespace exoid::experiments {

namespace {

nlohmann::json vectorJson(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

std::string list(const std::vector<int>& indices, const std::vector<std::string>& names) {
  std::string s;
  for (int k : indices) s += (s.empty() ? "" : ", ") + names[static_cast<std::size_t>(k)];
  return s.empty() ? "none" : s;
}

}  // namespace

void reportModel(const std::string& model_name, const std::string& json_out, std::ostream& out, const std::vector<std::string>& armature,
                 const core::ChainSelection& selection) {
  if (!json_out.empty()) core::checkOutputWritable(json_out);
  const LoadedChain loaded = loadChain(model_name, armature, selection);
  const auto& [path, chain_selection, chain, model, phi, base, robot] = loaded;
  const ident::BaseParameterOptions options;
  const std::vector<std::string> names = model.standardParameterNames();

  out << "Model " << path << " ('" << chain.name << "'): a serial chain of " << model.dof() << " revolute joints, "
      << names.size() << " standard parameters (10 per link about its joint, fc and fv per joint, Ia where the model has "
      << "armature).\n";
  TextTable joints({"joint", "link", "axis (link frame)", "origin in parent (m)", "mass (kg)"});
  for (const sim::ChainLinkBody& l : chain.links) {
    joints.addRow({l.joint, l.link, fmt(l.axis.x(), 4) + " " + fmt(l.axis.y(), 4) + " " + fmt(l.axis.z(), 4),
                   fmt(l.parent_p_joint_m.x(), 4) + " " + fmt(l.parent_p_joint_m.y(), 4) + " " + fmt(l.parent_p_joint_m.z(), 4),
                   fmt(l.mass_kg, 5)});
  }
  joints.print(out);
  if (!chain.left_out.empty()) {
    out << "Left out of the chain (bodies with joints of their own): ";
    for (const std::string& b : chain.left_out) out << b << (&b == &chain.left_out.back() ? "\n" : ", ");
  }
  const Eigen::VectorXd beta = base.combination * phi;
  out << "\nBase parameters (what torques identify; QR with column pivoting of the regressor at " << options.samples
      << " random states, seed " << options.seed << "): rank " << base.rank << " of " << names.size() << ".\n";
  TextTable t({"#", "base parameter", "true value"});
  for (int i = 0; i < base.rank; ++i) t.addRow({std::to_string(i + 1), base.names[static_cast<std::size_t>(i)], fmt(beta[i], 6)});
  t.print(out);
  printCombinations(out, base.names, base.combinations);
  out << "No torque shows (unidentifiable, whatever the motion): " << list(base.no_effect, names) << ".\n";
  for (const auto& [k, into] : base.regrouped) {
    out << "Regrouped: " << names[static_cast<std::size_t>(k)] << " acts only inside base parameter(s)";
    for (int i : into) out << " #" << i + 1;
    out << ".\n";
  }

  if (json_out.empty()) return;
  nlohmann::json j;
  j["tool"] = toolJson();
  j["command"] = "identifiability";
  j["model"] = {{"path", path}, {"name", chain.name}, {"gravity_mps2", vectorJson(chain.gravity_mps2)}};
  for (const sim::ChainLinkBody& l : chain.links) {
    j["model"]["joints"].push_back({{"joint", l.joint}, {"link", l.link}, {"axis", vectorJson(l.axis)},
                                    {"origin_m", vectorJson(l.parent_p_joint_m)}, {"mass_kg", l.mass_kg}});
  }
  j["model"]["left_out"] = chain.left_out;
  for (std::size_t k = 0; k < names.size(); ++k) j["standard_parameters"][names[k]] = phi[static_cast<Eigen::Index>(k)];
  j["base_parameters"] = {{"rank", base.rank}, {"samples", options.samples}, {"seed", options.seed}};
  for (int i = 0; i < base.rank; ++i) {
    nlohmann::json terms;
    for (Eigen::Index k = 0; k < base.combination.cols(); ++k) {
      if (base.combination(i, k) != 0.0) terms[names[static_cast<std::size_t>(k)]] = base.combination(i, k);
    }
    j["base_parameters"]["parameters"].push_back(
        {{"name", base.names[static_cast<std::size_t>(i)]}, {"combination", base.combinations[static_cast<std::size_t>(i)]}, {"terms", terms},
         {"true_value", beta[i]}});
  }
  for (int k : base.no_effect) j["base_parameters"]["no_effect"].push_back(names[static_cast<std::size_t>(k)]);
  writeJsonFile(json_out, j);
}

}  // namespace exoid::experiments

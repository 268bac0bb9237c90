#include "exoid/experiments/protocol/robot_loader.hpp"

#include "exoid/core/format.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/sim/model.hpp"

#include <nlohmann/json.hpp>

#include <fstream>
#include <stdexcept>

namespace exoid::experiments {

ident::ChainModel chainModel(const sim::SerialChain& chain) {
  ident::ChainModel model;
  model.name = chain.name;
  model.gravity_mps2 = chain.gravity_mps2;
  for (const sim::ChainLinkBody& l : chain.links) {
    ident::ChainJoint j;
    j.name = l.joint;
    j.link = l.link;
    j.parent_R_joint = l.parent_R_joint;
    j.parent_p_joint_m = l.parent_p_joint_m;
    j.axis = l.axis;
    j.friction = true;
    j.armature = l.armature_kgm2 != 0.0;
    model.joints.push_back(j);
  }
  model.validate();
  return model;
}

ident::ChainModel withArmature(ident::ChainModel model, const std::vector<std::string>& joints) {
  for (const std::string& name : joints) {
    bool found = false;
    for (ident::ChainJoint& j : model.joints) {
      if (name == "all" || j.name == name) {
        j.armature = true;
        found = true;
      }
    }
    if (!found) {
      const std::string all = core::joined(model.jointNames());
      throw std::invalid_argument("--armature: '" + name + "' is not a joint of " + model.name + " (its joints: " + all + "; or all)");
    }
  }
  return model;
}

Eigen::VectorXd standardParameters(const sim::SerialChain& chain) { return standardParameters(chain, chainModel(chain)); }

Eigen::VectorXd standardParameters(const sim::SerialChain& chain, const ident::ChainModel& model) {
  if (model.joints.size() != chain.links.size()) throw std::invalid_argument("standardParameters: the model is not this chain's");
  const std::vector<ident::JointParameterLayout> layout = model.layout();
  Eigen::VectorXd phi(model.standardParameterCount());
  for (std::size_t i = 0; i < chain.links.size(); ++i) {
    const sim::ChainLinkBody& l = chain.links[i];
    phi.segment<ident::kLinkParams>(layout[i].link) = ident::linkParameters(l.mass_kg, l.com_m, l.inertia_com_kgm2);
    phi.segment<2>(layout[i].friction) << l.coulomb_Nm, l.damping_Nms;
    if (layout[i].armature >= 0) phi[layout[i].armature] = l.armature_kgm2;
  }
  return phi;
}

bool isApalLeg(const std::string& name_or_path, const core::ChainSelection& selection) {
  return selection.empty() && sim::isApalLegModel(sim::modelPathFor(name_or_path));
}

LoadedChain loadChain(const std::string& name_or_path, const std::vector<std::string>& armature, const core::ChainSelection& selection) {
  LoadedChain c;
  c.path = sim::modelPathFor(name_or_path);
  c.selection = selection;
  c.chain = sim::serialChainFromFile(c.path, selection);
  c.model = withArmature(chainModel(c.chain), armature);
  c.phi = standardParameters(c.chain, c.model);
  c.robot = ident::chainRobot(c.model);
  c.base = c.robot.basis;
  return c;
}

LoadedChain movingBase(LoadedChain loaded, const std::vector<ident::Dataset>& records, const ident::SignalOptions& signals) {
  bool moving = false;
  for (const ident::Dataset& d : records) moving = moving || usesBaseMotion(d, signals);
  if (!moving) throw std::invalid_argument("--moving-base-parameters: no record carries base-motion terms (the IMU columns base_acc_x, "
                                           "base_acc_z, base_gyro_y, with --base-terms auto or on and the parallel processing)");
  ident::BaseParameterOptions o;
  o.planar_base_motion = true;
  loaded.robot = ident::chainRobot(loaded.model, o);
  loaded.base = loaded.robot.basis;
  return loaded;
}

void checkRecordedChain(const std::string& source, const std::string& recorded, const LoadedChain& loaded) {
  if (recorded == loaded.selection.label() || recorded == loaded.selection.options()) return;
  core::ChainSelection was;
  sim::SerialChain other;
  try {
    was = core::parseChainSelection(recorded);
    if (was.label() == loaded.selection.label()) return;
    other = sim::serialChainFromFile(loaded.path, was);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(source + ": not data of a chain of " + loaded.path + ": " + e.what());
  }
  std::string differs;
  if (other.jointNames() != loaded.chain.jointNames()) {
    differs = "its joints (" + core::joined(other.jointNames(), ", ") + ")";
  } else if (!other.gravity_mps2.isApprox(loaded.chain.gravity_mps2, 1e-12)) {
    differs = "gravity in its base frame";
  }
  for (std::size_t j = 0; differs.empty() && j < other.links.size(); ++j) {
    const sim::ChainLinkBody &a = other.links[j], &b = loaded.chain.links[j];
    if (!a.parent_R_joint.isApprox(b.parent_R_joint, 1e-12) || (a.parent_p_joint_m - b.parent_p_joint_m).norm() > 1e-12 ||
        !a.axis.isApprox(b.axis, 1e-12)) {
      differs = "joint " + a.joint + "'s placement or axis";
    }
  }
  if (differs.empty()) return;
  throw std::invalid_argument(source + ": data of the chain '" + was.label() + "' of " + loaded.path + ", read as '" + loaded.selection.label() +
                              "', which differ in " + differs + ": give the data's --base, --tip and --lock");
}

std::function<void(const std::string&, const ident::Dataset&)> recordOfChain(const LoadedChain& loaded) {
  return [loaded](const std::string& path, const ident::Dataset& d) {  // a copy: the check may outlive the caller's chain
    if (const auto recorded = d.metadata("chain_selection")) checkRecordedChain(path + " (metadata 'chain_selection')", *recorded, loaded);
  };
}

Eigen::VectorXd truthFromSidecar(const std::string& path, const LoadedChain& loaded) {
  std::ifstream in(path);
  const nlohmann::json t = nlohmann::json::parse(in, nullptr, false);
  if (t.is_discarded() || !t.contains("truth") || !t["truth"].contains("standard_parameters") || !t["truth"]["standard_parameters"].is_object()) {
    throw std::invalid_argument("--truth '" + path + "': expected a chain simulation's sidecar with truth.standard_parameters");
  }
  if (t.contains("model") && t["model"].is_object() && t["model"].contains("selection")) {  // an older sidecar does not say
    const nlohmann::json& recorded = t["model"]["selection"];
    if (!recorded.is_string()) throw std::invalid_argument("--truth '" + path + "': model.selection is not a string");
    checkRecordedChain("--truth '" + path + "' (model.selection)", recorded.get<std::string>(), loaded);
  }
  const nlohmann::json& given = t["truth"]["standard_parameters"];
  const std::vector<std::string> names = loaded.model.standardParameterNames();
  Eigen::VectorXd phi = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(names.size()));
  bool any = false;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (!given.contains(names[i])) continue;
    if (!given[names[i]].is_number()) throw std::invalid_argument("--truth '" + path + "': truth.standard_parameters." + names[i] + " is not a number");
    phi[static_cast<Eigen::Index>(i)] = given[names[i]].get<double>();
    any = true;
  }
  if (!any) throw std::invalid_argument("--truth '" + path + "': none of the model's standard parameters (a sidecar of another model?)");
  return loaded.base.combination * phi;
}

}  // namespace exoid::experiments

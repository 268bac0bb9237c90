#include "exoid/experiments/protocol/chain_bridge.hpp"

#include "exoid/sim/model.hpp"

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
      std::string all;
      for (const std::string& j : model.jointNames()) all += (all.empty() ? "" : ", ") + j;
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

LoadedChain loadChain(const std::string& name_or_path, const std::vector<std::string>& armature) {
  LoadedChain c;
  c.path = sim::modelPathFor(name_or_path);
  c.chain = sim::serialChainFromFile(c.path);
  c.model = withArmature(chainModel(c.chain), armature);
  c.phi = standardParameters(c.chain, c.model);
  c.robot = ident::chainRobot(c.model);
  c.base = c.robot.basis;
  return c;
}

}  // namespace exoid::experiments

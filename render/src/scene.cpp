#include "exoid/render/scene.hpp"

#include "exoid/render/leg_scene.hpp"
#include "exoid/sim/urdf_rig.hpp"

#include <stdexcept>

namespace exoid::render {

ChainScene::ChainScene(const std::string& model_path, const std::vector<std::string>& joints, const core::ChainSelection& selection)
    : model_(sim::isUrdfFile(model_path) ? sim::compileUrdfRig(model_path, selection, false, true) : sim::loadMjcfFile(model_path)),
      data_(sim::makeData(model_.get())) {
  for (const std::string& name : joints) {
    const int j = mj_name2id(model_.get(), mjOBJ_JOINT, name.c_str());
    if (j < 0) throw std::invalid_argument("'" + model_path + "' has no joint '" + name + "' (the record's joints must be the model's)");
    qposadr_.push_back(model_->jnt_qposadr[j]);
  }
  mj_kinematics(model_.get(), data_.get());
}

void ChainScene::pose(const Track& track, std::size_t row) {
  if (track.joints.size() != qposadr_.size()) throw std::invalid_argument("the scene was opened for another track's joints");
  for (std::size_t k = 0; k < qposadr_.size(); ++k) data_->qpos[qposadr_[k]] = track.joints[k].q_rad[row];
  mj_kinematics(model_.get(), data_.get());
}

bool ChainScene::framed(int g) const { return model_->geom_bodyid[g] != 0 && model_->geom_type[g] != mjGEOM_PLANE; }

std::unique_ptr<Scene> openScene(const std::string& model_path, const Track& track, double base_motion_gain,
                                 const core::ChainSelection& selection) {
  if (sim::isApalLegModel(model_path)) return std::make_unique<LegScene>(model_path, track.hasBase(), base_motion_gain);
  std::vector<std::string> joints;
  for (const TrackJoint& j : track.joints) joints.push_back(j.name);
  return std::make_unique<ChainScene>(model_path, joints, selection);
}

}  // namespace exoid::render

#include "exoid/render/leg_scene.hpp"

#include "exoid/core/format.hpp"

#include <cstring>
#include <stdexcept>

namespace exoid::render {

namespace {

sim::ModelVariant variantFor(bool with_mount) {
  sim::ModelVariant v;
  v.vibration_level = with_mount ? 1.0 : 0.0;  // any level > 0 keeps the mount joints
  return v;
}

// Colors per body on the compiled copy: materials are dropped for these geoms (their rgba would
// otherwise win), each geom keeps its alpha, joint housings are a darker shade of their body.
void applyColors(mjModel* m, const sim::LegIndices& x, const LegColors& c) {
  const std::pair<int, const std::array<float, 3>*> bodies[] = {
      {x.body_pedestal, &c.pedestal}, {x.body_trunk, &c.trunk}, {x.body_thigh, &c.thigh},
      {x.body_shank, &c.shank},       {x.body_cylinder, &c.cylinder}, {x.body_rod, &c.rod}};
  for (int g = 0; g < m->ngeom; ++g) {
    const std::array<float, 3>* rgb = nullptr;
    for (const auto& [body, color] : bodies) {
      if (body >= 0 && m->geom_bodyid[g] == body) rgb = color;
    }
    if (!rgb) continue;
    float* rgba = m->geom_rgba + 4 * g;
    const bool default_rgba = rgba[0] == 0.5f && rgba[1] == 0.5f && rgba[2] == 0.5f && rgba[3] == 1.0f;
    float alpha = rgba[3];
    if (default_rgba && m->geom_matid[g] >= 0) alpha = m->mat_rgba[4 * m->geom_matid[g] + 3];
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    const float shade = (name && std::strstr(name, "housing")) ? 0.55f : 1.0f;
    for (int k = 0; k < 3; ++k) rgba[k] = shade * (*rgb)[static_cast<std::size_t>(k)];
    rgba[3] = alpha;
    m->geom_matid[g] = -1;
  }
}

}  // namespace

LegScene::LegScene(const std::string& model_path, bool with_mount, double base_motion_gain, const LegColors& colors)
    : leg_(sim::loadLeg(model_path, variantFor(with_mount))), base_motion_gain_(base_motion_gain) {
  mjModel* m = leg_.model.get();
  data_ = sim::makeData(m);
  four_bar_.emplace(m, leg_.idx);
  applyColors(m, leg_.idx, colors);
  setPose(Pose{});
}

Pose poseAt(const Track& track, std::size_t row, double base_motion_gain) {
  if (track.joints.size() != 2) throw std::invalid_argument("the APAL leg is posed by a track of 2 joints (hip, knee), got " + core::toText(track.joints.size()));
  Pose pose{track.joints[0].q_rad[row], track.joints[1].q_rad[row]};
  if (track.hasBase()) {
    pose.base_x_m = base_motion_gain * track.base_x_m[row];
    pose.base_z_m = base_motion_gain * track.base_z_m[row];
    pose.base_pitch_rad = base_motion_gain * track.base_pitch_rad[row];
  }
  return pose;
}

void LegScene::setPose(const Pose& pose) {
  const mjModel* m = leg_.model.get();
  mjData* d = data_.get();
  const sim::LegIndices& x = leg_.idx;
  mju_zero(d->qvel, m->nv);
  sim::setLegState(m, d, x, *four_bar_, {pose.q_hip_rad, pose.q_knee_rad}, {0.0, 0.0});
  if (x.hasMount()) {
    d->qpos[x.mount_qadr[0]] = pose.base_x_m;
    d->qpos[x.mount_qadr[1]] = pose.base_z_m;
    d->qpos[x.mount_qadr[2]] = pose.base_pitch_rad;
  }
  mj_forward(m, d);
}

void LegScene::pose(const Track& track, std::size_t row) { setPose(poseAt(track, row, base_motion_gain_)); }

bool LegScene::framed(int g) const {
  const mjModel* m = leg_.model.get();
  for (int b = m->geom_bodyid[g]; b > 0; b = m->body_parentid[b]) {
    if (b == leg_.idx.body_trunk) return true;
  }
  return false;
}

}  // namespace exoid::render

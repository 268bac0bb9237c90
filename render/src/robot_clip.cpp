#include "exoid/render/robot_clip.hpp"

#include "exoid/core/atomic_file.hpp"
#include "exoid/core/format.hpp"
#include "exoid/render/framing.hpp"
#include "exoid/render/png.hpp"
#include "exoid/render/video_writer.hpp"
#include "exoid/sim/model.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace exoid::render {

void ChainClipOptions::validate() const {
  render.validate();
  overlay.validate();
  if (!std::isfinite(fps) || fps <= 0.0 || fps > 240.0) throw std::invalid_argument("'fps' must be in (0, 240], got " + core::toText(fps));
}

namespace {

struct ChainPoser {
  sim::ModelPtr model;
  sim::DataPtr data;
  std::vector<int> qposadr;

  ChainPoser(const std::string& path, const std::vector<std::string>& joints) : model(sim::loadMjcfFile(path)), data(sim::makeData(model.get())) {
    for (const std::string& name : joints) {
      const int j = mj_name2id(model.get(), mjOBJ_JOINT, name.c_str());
      if (j < 0) throw std::invalid_argument("'" + path + "' has no joint '" + name + "' (the record's joints must be the model's)");
      qposadr.push_back(model->jnt_qposadr[j]);
    }
  }
  void pose(const Eigen::MatrixXd& q, Eigen::Index row) {
    for (std::size_t k = 0; k < qposadr.size(); ++k) data->qpos[qposadr[k]] = q(row, static_cast<Eigen::Index>(k));
    mj_kinematics(model.get(), data.get());
  }
};

// The x-z box the moving bodies' geoms sweep (bounding spheres; the world's own geoms, e.g. the
// floor, left out).
SweptBox chainSweptBox(ChainPoser& p, const Eigen::MatrixXd& q) {
  const double inf = std::numeric_limits<double>::infinity();
  SweptBox b{inf, -inf, inf, -inf};
  const mjModel* m = p.model.get();
  constexpr int kSamples = 120;
  for (int s = 0; s < kSamples; ++s) {
    p.pose(q, static_cast<Eigen::Index>(std::llround(double(s) * double(q.rows() - 1) / double(kSamples - 1))));
    for (int g = 0; g < m->ngeom; ++g) {
      if (m->geom_bodyid[g] == 0 || m->geom_type[g] == mjGEOM_PLANE) continue;
      const double r = m->geom_rbound[g];
      const mjtNum* x = p.data->geom_xpos + 3 * g;
      b.x_min = std::min(b.x_min, x[0] - r);
      b.x_max = std::max(b.x_max, x[0] + r);
      b.z_min = std::min(b.z_min, x[2] - r);
      b.z_max = std::max(b.z_max, x[2] + r);
    }
  }
  return b;
}

}  // namespace

void renderChain(const std::string& model_path, const std::vector<std::string>& joints, const Eigen::VectorXd& t_s,
                 const Eigen::MatrixXd& q_rad, const std::string& out, const ChainClipOptions& options_in,
                 std::optional<double> frame_s, const OverlayTrack* overlay) {
  options_in.validate();
  if (q_rad.cols() != static_cast<Eigen::Index>(joints.size()) || q_rad.rows() != t_s.size() || t_s.size() < 2) {
    throw std::invalid_argument("render: expected angles of " + core::toText(joints.size()) + " joints at each of >= 2 times");
  }
  if (overlay && static_cast<Eigen::Index>(overlay->t_s.size()) != t_s.size()) {
    throw std::invalid_argument("render: the overlay's track has " + core::toText(overlay->t_s.size()) + " samples, the record " +
                                core::toText(t_s.size()));
  }
  const std::optional<OverlayBuilder> builder = overlay ? std::optional<OverlayBuilder>(OverlayBuilder(*overlay, options_in.overlay)) : std::nullopt;
  ChainPoser poser(model_path, joints);
  ChainClipOptions o = options_in;
  if (o.auto_frame) {
    // The plots take the lower right: the leg keeps to the rest of the view (as the APAL leg's clip).
    const bool plots = overlay && o.overlay.plot && overlay->hasTorque();
    o.render.camera = frameBox(chainSweptBox(poser, q_rad), o.render.camera, poser.model->vis.global.fovy,
                               double(o.render.width) / double(o.render.height), plots ? 0.55 : 1.0);
  }
  OffscreenRenderer renderer(poser.model.get(), o.render);
  const double t0 = t_s[0], t1 = t_s[t_s.size() - 1];
  const auto rowAt = [&](double t) {
    const auto it = std::lower_bound(t_s.data(), t_s.data() + t_s.size(), t);
    return std::min<Eigen::Index>(static_cast<Eigen::Index>(it - t_s.data()), t_s.size() - 1);
  };
  const auto draw = [&](Eigen::Index row) -> const Image& {
    poser.pose(q_rad, row);
    if (!builder) return renderer.render(poser.model.get(), poser.data.get());
    const Overlay ov = builder->at(static_cast<std::size_t>(row));
    return renderer.render(poser.model.get(), poser.data.get(), &ov);
  };
  if (frame_s) {
    if (!(*frame_s >= t0 && *frame_s <= t1)) {
      throw std::invalid_argument("--frame " + core::toText(*frame_s) + " is outside the record [" + core::toText(t0) + ", " + core::toText(t1) + "] s");
    }
    core::writeFileAtomically(out, encodePng(draw(rowAt(*frame_s))));
    return;
  }
  VideoWriter video(out, o.render.width, o.render.height, o.fps, o.ffmpeg);
  for (long k = 0; t0 + double(k) / o.fps <= t1 + 1e-12; ++k) video.write(draw(rowAt(t0 + double(k) / o.fps)));  // frames at k / fps, no accumulated rounding
  video.finish();
}

}  // namespace exoid::render

#pragma once
// A robot posed for drawing from a track's rows: the APAL leg (LegScene: its four-bar closed, its
// pedestal moved) or any serial chain's MJCF (ChainScene: its hinges posed by name). A clip and
// its framing draw both the same way (clip.hpp, framing.hpp).
#include "exoid/core/tree_selection.hpp"
#include "exoid/render/track.hpp"
#include "exoid/sim/model.hpp"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace exoid::render {

class Scene {
 public:
  virtual ~Scene() = default;
  /// Poses the robot as the track records it at `row` and computes the kinematics.
  virtual void pose(const Track& track, std::size_t row) = 0;
  virtual mjModel* model() = 0;
  virtual mjData* data() = 0;
  /// Whether geom `g` belongs to what the camera keeps in view (framing.hpp).
  virtual bool framed(int g) const = 0;
};

/// Any serial chain's MJCF, or the chain `selection` picks out of a URDF (drawn as sim::urdfRigMjcf's
/// shapes), its joints posed by the track's joint names (zero elsewhere); every geom of a moving
/// body is framed (the world's, e.g. a floor, is not).
class ChainScene final : public Scene {
 public:
  /// Throws sim::MujocoError, or std::invalid_argument naming a joint the model lacks.
  ChainScene(const std::string& model_path, const std::vector<std::string>& joints, const core::ChainSelection& selection = {});
  void pose(const Track& track, std::size_t row) override;
  mjModel* model() override { return model_.get(); }
  mjData* data() override { return data_.get(); }
  bool framed(int g) const override;

 private:
  sim::ModelPtr model_;
  sim::DataPtr data_;
  std::vector<int> qposadr_;  // per track joint
};

/// The scene of `model_path` for `track`: the APAL leg's when the file is its MJCF (the mount
/// kept when the track moves the pedestal, that motion scaled by base_motion_gain), else the
/// chain's (`selection` out of a URDF's tree). Throws as the scene's constructor.
std::unique_ptr<Scene> openScene(const std::string& model_path, const Track& track, double base_motion_gain = 1.0,
                                 const core::ChainSelection& selection = {});

}  // namespace exoid::render

#pragma once
// Loading the leg model: RAII owners of mjModel/mjData, the named elements the simulator uses,
// and model variants applied to the compiled model (no XML editing by the user).
#include "exoid/sim/mujoco_hooks.hpp"

#include <mujoco/mujoco.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace exoid::sim {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;  ///< owns an mjModel
using DataPtr = std::unique_ptr<mjData, DataDeleter>;     ///< owns an mjData

/// dataPath("models/apal_leg.xml") (see data_dir.hpp).
std::string defaultModelPath();
/// The built-in models by name: "apal" (models/apal_leg.xml, the default) and "leg3" (the 3-DOF
/// hip-knee-ankle leg, models/leg3.xml; its URDF is models/leg3.urdf). Anything else is taken as a
/// file path and returned unchanged.
std::string modelPathFor(const std::string& name_or_path);

/// Whole file as bytes; throws std::invalid_argument("cannot read model file '<path>'...").
std::string readFileBytes(const std::string& path);

/// Compiles MJCF text (given as bytes, e.g. after stripMountJoints). `source` names it in
/// errors. Throws MujocoError("<source>: <MuJoCo's message>").
ModelPtr compileMjcf(const std::string& xml, const std::string& source);
/// mj_loadXML of a file; throws MujocoError naming the path (missing file, bad XML, ...).
ModelPtr loadMjcfFile(const std::string& path);
/// Whether the file is the APAL leg's MJCF (its model named "apal_leg"), whose plant (the four-bar
/// cylinder, the pedestal) is simulated and drawn as such; a URDF never is. Throws as loadMjcfFile.
bool isApalLegModel(const std::string& path);
/// Whether the file is a URDF: its root element is <robot> (whatever its name: a URDF saved as .xml
/// is one); an unreadable file by its extension (.urdf in any case). Anything else is read as MJCF.
bool isUrdfFile(const std::string& path);
/// mj_makeData; throws MujocoError on failure.
DataPtr makeData(const mjModel* m);
/// One step of the model's integrator from the state mj_forward has evaluated (what mj_step does
/// after its own mj_forward). RK4 is the models' choice: with Euler, position differences of the
/// recorded states lag the recorded velocity by dt qacc / 2 (a simulator artifact, not physics).
void integrateStep(const mjModel* m, mjData* d);
/// The model's custom numeric `name` (its first value), or `fallback` when it has none.
double numericOr(const mjModel* m, const std::string& name, double fallback);

/// Removes every self-closing <joint .../> element with class="mount" from MJCF text (the
/// pedestal's compliant mount), which welds the pedestal to the world exactly: no dofs left.
/// Throws std::invalid_argument if there is none or a mount joint is not self-closing.
std::string stripMountJoints(const std::string& xml, const std::string& source);

/// FNV-1a 64-bit hash of bytes (model provenance in the sidecar).
std::uint64_t fnv1a64(const std::string& bytes);
/// 16 lowercase hex digits.
std::string toHex(std::uint64_t v);

/// Variants of the model chosen at run time.
struct ModelVariant {
  /// Scales the mass and inertia of the cylinder and rod; range [0, 10]. 0 = no moving actuator
  /// mass: the 2-link model is then exact (the massless loop is closed kinematically, see
  /// LegModel::kinematic_loop). Default 1 (the model's 0.8 + 0.4 kg).
  double cylinder_mass_scale = 1.0;
  /// Pedestal mount: 0 = welded (mount joints removed, exactly still); L > 0 scales the XML's
  /// level-1 mount stiffness by 1/L^2 and damping by 1/L (same damping ratio, natural
  /// frequencies divided by L, static deflections times L^2). Range [0, 20].
  double vibration_level = 0.0;
  /// Overrides of the joint friction (N m, N m s/rad); unset = the model's values
  /// (Coulomb from the custom numerics exoid_fc_*, viscous = joint damping). Must be >= 0.
  std::optional<double> fc_hip_Nm, fv_hip_Nms, fc_knee_Nm, fv_knee_Nms;
  /// Reflected rotor/actuator inertia on the knee's own diagonal (MuJoCo armature, kg m^2; unset
  /// = the model's, 0): what a geared motor or a hydraulic piston adds to M22 but not to M12. The
  /// 10-parameter model cannot hold it (identify --knee-armature estimates it). Must be >= 0.
  std::optional<double> knee_armature_kgm2;
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

/// Coulomb friction applied by the simulator as the smooth generalized force
/// -fc * tanh(qd / v0) (qfrc_applied): |tanh(x) - sgn(x)| < 2 exp(-2|x|), so it equals the
/// paper's fc sgn(qd) to 1e-8 relative once |qd| > 10 v0 (20 mrad/s for v0 = 2 mrad/s).
struct CoulombFriction {
  std::array<double, 2> fc_Nm{0.0, 0.0};  ///< hip, knee
  double v0_radps = 2e-3;                 ///< tanh smoothing velocity
  double torque(int joint, double qd) const;  ///< friction torque fc tanh(qd/v0) (opposes motion when subtracted)
};

/// Addresses of the named model elements (-1 when absent and optional).
struct LegIndices {
  int body_pedestal = -1, body_trunk = -1, body_thigh = -1, body_shank = -1, body_cylinder = -1,
      body_rod = -1;
  std::array<int, 2> jnt{-1, -1};       ///< hip, knee joint ids
  std::array<int, 2> qadr{-1, -1};      ///< qpos addresses of hip, knee
  std::array<int, 2> vadr{-1, -1};      ///< dof addresses of hip, knee
  std::array<int, 2> act{-1, -1};       ///< hip_motor, knee_motor
  int jnt_cyl = -1, jnt_rod = -1;       ///< cylinder_hinge, rod_slide
  int qadr_cyl = -1, qadr_rod = -1, vadr_cyl = -1, vadr_rod = -1;
  std::array<int, 3> mount_jnt{-1, -1, -1};   ///< mount_x, mount_z, mount_pitch (or -1)
  std::array<int, 3> mount_qadr{-1, -1, -1};
  std::array<int, 3> mount_vadr{-1, -1, -1};
  int eq_loop = -1, eq_hip_lock = -1;
  int site_imu = -1;  ///< the pedestal IMU's site (on the trunk)
  bool hasMount() const { return mount_jnt[0] >= 0; }
};

/// Finds the names listed in models/apal_leg.xml; throws std::invalid_argument naming the
/// missing element and `source`.
LegIndices findLegIndices(const mjModel* m, const std::string& source);

/// A compiled leg model with the variant applied.
struct LegModel {
  ModelPtr model;
  LegIndices idx;
  CoulombFriction coulomb;
  std::string path;          ///< the MJCF file
  std::uint64_t xml_fnv1a64 = 0;
  std::size_t xml_bytes = 0;
  bool welded = false;       ///< mount joints removed
  /// Cylinder mass scale 0: the loop equality is disabled (a massless closed loop has a
  /// singular mass matrix) and the passive joints follow the analytic closure kinematically;
  /// they carry a tiny armature (kMasslessArmature) so the mass matrix stays regular. They are
  /// decoupled from hip and knee, so the leg is exactly the 2-link model.
  bool kinematic_loop = false;
  ModelVariant variant;
};

inline constexpr double kMasslessArmature = 1e-9;  ///< kg m^2 or kg, passive dofs when massless

/// Loads `path` (default variant if omitted), optionally welding the pedestal regardless of
/// variant.vibration_level (the "ideal rig" used for inverse dynamics). Throws MujocoError or
/// std::invalid_argument with the path in the message.
LegModel loadLeg(const std::string& path, const ModelVariant& variant = {}, bool force_welded = false);

}  // namespace exoid::sim

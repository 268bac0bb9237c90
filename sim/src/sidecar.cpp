#include "exoid/sim/sidecar.hpp"

#include "exoid/core/atomic_file.hpp"

#include "exoid/sim/table.hpp"
#include "exoid/sim/trajectory_json.hpp"

namespace exoid::sim {

namespace {
nlohmann::json vec2(const Eigen::Vector2d& v) { return {{"hip", v[0]}, {"knee", v[1]}}; }
template <class T>
nlohmann::json opt(const std::optional<T>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}
}  // namespace

nlohmann::json configJson(const SimConfig& c) {
  const core::FourierSeries spec = c.trajectorySpec();
  nlohmann::json j;
  j["model_path"] = c.model_path;
  j["trajectory"] = c.trajectory;
  j["trajectory_spec"] = trajectoryJson(spec, {"hip", "knee"});
  j["ramp_s"] = c.ramp_s;
  j["record_after_ramp"] = c.record_after_ramp;
  j["duration_s"] = c.duration_s;
  j["dt_s"] = c.dt_s;
  j["sensors"] = {{"noise_q_deg", c.sensors.noise_q_deg},
                  {"quantisation_deg", c.sensors.quantisation_deg},
                  {"encoder_backlash_deg", c.sensors.encoder_backlash_deg},
                  {"noise_tau_Nm", c.sensors.noise_tau_Nm},
                  {"tau_bias_Nm", {{"hip", c.sensors.tau_bias_Nm.empty() ? 0.0 : c.sensors.tau_bias_Nm[0]},
                                   {"knee", c.sensors.tau_bias_Nm.empty() ? 0.0 : c.sensors.tau_bias_Nm[1]}}},
                  {"tau_bandwidth_Hz", c.sensors.tau_bandwidth_Hz},
                  {"imu_acc_noise_mps2", c.sensors.imu_acc_noise_mps2},
                  {"imu_gyro_noise_radps", c.sensors.imu_gyro_noise_radps}};
  j["actuators"] = {{"hip_bandwidth_Hz", c.actuators.hip_bandwidth_Hz},
                    {"hip_damping", c.actuators.hip_damping},
                    {"knee_bandwidth_Hz", c.actuators.knee_bandwidth_Hz},
                    {"knee_damping", c.actuators.knee_damping}};
  j["variant"] = {{"cylinder_mass_scale", c.variant.cylinder_mass_scale},
                  {"vibration_level", c.variant.vibration_level},
                  {"fc_hip_Nm", opt(c.variant.fc_hip_Nm)},
                  {"fv_hip_Nms", opt(c.variant.fv_hip_Nms)},
                  {"fc_knee_Nm", opt(c.variant.fc_knee_Nm)},
                  {"fv_knee_Nms", opt(c.variant.fv_knee_Nms)},
                  {"knee_armature_kgm2", opt(c.variant.knee_armature_kgm2)}};
  j["floor"] = {{"force_x_amplitude_N", c.floor.force_x_amplitude_N},
                {"force_z_amplitude_N", c.floor.force_z_amplitude_N},
                {"frequency_Hz", c.floor.frequency_Hz},
                {"random_std_N", c.floor.random_std_N}};
  j["gains"] = {{"kp_Nm_per_rad", vec2(c.gains.kp_Nm_per_rad)},
                {"ki_Nm_per_rad_s", vec2(c.gains.ki_Nm_per_rad_s)},
                {"kd_Nms_per_rad", vec2(c.gains.kd_Nms_per_rad)},
                {"derivative_cutoff_Hz", c.gains.derivative_cutoff_Hz},
                {"integral_limit_Nm", c.gains.integral_limit_Nm}};
  j["feedforward"] = c.feedforward;
  j["feedforward_model"] =
      c.feedforward_model == SimConfig::ControllerModel::kRigidLinks ? "rigid links (no cylinder mass)" : "rig as simulated";
  j["seed"] = c.seed;
  j["exact_columns"] = c.exact_columns;
  j["max_loop_error_m"] = c.max_loop_error_m;
  return j;
}

nlohmann::json paramsJson(const ParamArray& x) {
  nlohmann::json j = nlohmann::json::object();
  for (int i = 0; i < kNumParams; ++i) j[paramNames()[i]] = x[i];
  return j;
}

nlohmann::json sidecar(const SimResult& r, const std::string& exoid_version) {
  nlohmann::json j;
  j["format"] = "exoid-sim-sidecar/2";  // 2: trajectory_spec in sim/trajectory_json.hpp's form
  j["exoid_version"] = exoid_version;
  j["mujoco_version"] = r.mujoco_version;
  j["mujoco_header_version"] = mjVERSION_HEADER;
  j["model"] = {{"path", r.config.model_path}, {"fnv1a64", r.model_fnv1a64}, {"bytes", r.model_bytes}};
  j["seed"] = r.config.seed;
  j["settings"] = configJson(r.config);
  j["columns"] = r.table.names;
  j["rows"] = r.table.rows();
  nlohmann::json units = nlohmann::json::object();
  for (int i = 0; i < kNumParams; ++i) units[paramNames()[i]] = paramUnits()[i];
  const ParamBand& b = r.lumped_band;
  j["truth"] = {
      {"parameter_order", paramNames()},
      {"units", units},
      {"rigid",
       {{"description",
         "X of the bare rigid links (thigh; shank + foot) from the compiled model at qpos = 0: "
         "exact for the 2-link model when cylinder_mass_scale = 0 and vibration_level = 0"},
        {"parameters", paramsJson(r.truth.x)}}},
      {"lumped_band",
       {{"description",
         "min/max over the record's knee range of X(q2): cylinder lumped rigidly into the thigh and "
         "rod into the shank, frozen at the pose of knee angle q2 (relative-motion terms "
         "neglected); cylinder mass as run"},
        {"q_knee_min_rad", b.q2_min_rad},
        {"q_knee_max_rad", b.q2_max_rad},
        {"samples", b.samples},
        {"min", paramsJson(b.min)},
        {"max", paramsJson(b.max)}}},
      {"knee_armature",
       {{"description", "reflected inertia on the knee's own diagonal (MuJoCo armature): the 11th parameter Ia2 of "
                        "identify --knee-armature; the 10 parameters above exclude it"},
        {"Ia2", r.truth.knee_armature_kgm2}}},
      {"thigh_length_m", r.truth.thigh_length_m},
      {"gravity_mps2", r.truth.gravity_mps2},
      {"friction",
       {{"viscous", "fv = joint damping (MuJoCo passive force; explicit in the RK4 integrator)"},
        {"coulomb",
         "applied as qfrc_applied = -fc tanh(qd / v0); equals fc sgn(qd) to < 2 exp(-2|qd|/v0) "
         "relative, i.e. exactly the paper's term except for samples with |qd| < ~10 v0 near "
         "velocity reversals; fc is the truth of the paper's fc"},
        {"v0_radps", r.truth.coulomb_v0_radps}}},
      {"ideal_torque_columns",
       "tau_*_ideal: inverse dynamics of the same model with the pedestal welded and the loop rigid, at "
       "the exact joint states; fit X to them for the record's best-fit truth"}};
  const SimStats& s = r.stats;
  j["stats"] = {
      {"tracking_error_deg",
       {{"hip", {{"rms", s.tracking_hip.rms_deg}, {"max", s.tracking_hip.max_deg}}},
        {"knee", {{"rms", s.tracking_knee.rms_deg}, {"max", s.tracking_knee.max_deg}}}}},
      {"loop_error_m", {{"start", s.loop_error_start_m}, {"max", s.loop_error_max_m}, {"rms", s.loop_error_rms_m}}},
      {"pedestal_max_abs",
       {{"x_m", s.base_x_max_abs_m}, {"z_m", s.base_z_max_abs_m}, {"pitch_rad", s.base_pitch_max_abs_rad}}},
      {"tau_rms_Nm", {{"hip", s.tau_rms_hip_Nm}, {"knee", s.tau_rms_knee_Nm}}},
      {"wall_time_s", s.wall_time_s},
      {"loop_time_s", s.loop_time_s}};
  return j;
}

void writeJson(const nlohmann::json& j, const std::string& path) { core::writeFileAtomically(path, j.dump(2) + "\n"); }

std::string sidecarPathOf(const std::string& csv) {
  const auto dot = csv.rfind('.'), slash = csv.rfind('/');
  const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  return (has_ext ? csv.substr(0, dot) : csv) + ".json";
}

}  // namespace exoid::sim

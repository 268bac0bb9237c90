#pragma once
// Ground truth: the paper's X = [Mxt, Myt, Jt, fc1, fv1, Mxs, Mys, Js, fc2, fv2] from a compiled
// model (paper.md, "From a compiled MuJoCo model"), from a URDF, and the effective X(q2) with the
// four-bar's cylinder and rod lumped into thigh and shank.
//
// Link sums about a joint j of a set of bodies B, in the joint body's frame (x anterior, z up
// the link at q = 0): with d = the body COM relative to the joint, I_yy = the body inertia's yy
// entry in that frame,
//   Mx = sum m (-d_z),  My = sum m (-d_x),  J = sum (I_yy + m (d_x^2 + d_z^2)).
// Then Mxs, Mys, Js = the shank sums about the knee; Mxt = Mx_thigh + ms Lt, Myt = My_thigh,
// Jt = J_thigh + ms Lt^2 + Js + hip armature; fv = joint damping; fc = the Coulomb setting.
#include "exoid/sim/four_bar.hpp"
#include "exoid/sim/model.hpp"

#include <array>
#include <string>

namespace exoid::sim {

inline constexpr int kNumParams = 10;
using ParamArray = std::array<double, kNumParams>;
/// "Mxt", "Myt", "Jt", "fc1", "fv1", "Mxs", "Mys", "Js", "fc2", "fv2".
const std::array<const char*, kNumParams>& paramNames();
/// SI units of the parameters, same order.
const std::array<const char*, kNumParams>& paramUnits();

struct Truth {
  ParamArray x{};                 ///< X of the bare rigid links (no cylinder, no rod)
  double thigh_length_m = 0.0;    ///< Lt: hip axis to knee axis
  double gravity_mps2 = 0.0;      ///< |g|
  double coulomb_v0_radps = 0.0;  ///< smoothing of the simulated Coulomb term (0 for a URDF)
  double shank_mass_kg = 0.0, thigh_mass_kg = 0.0;
  /// Knee armature (kg m^2): the 11th parameter Ia2 of identify --knee-armature; not in x.
  double knee_armature_kgm2 = 0.0;
  std::string source;             ///< file it came from
};

/// X of the bare rigid links of a compiled leg: thigh = the `thigh` body alone; shank = `shank`
/// and every body welded below it (no dofs). Cylinder and rod are excluded. Requires hip/knee
/// axes along y and the knee on the thigh's -z axis; throws std::invalid_argument otherwise. A
/// knee armature is reported in knee_armature_kgm2 (the 10-parameter model cannot hold it).
Truth rigidTruth(const LegModel& leg);

/// Truth of an MJCF file (default variant).
Truth truthFromModel(const std::string& path);

/// Truth of a URDF's rigid links (urdfdom): joints `hip` and `knee` (revolute, axis 0 1 0),
/// the shank plus links fixed below it; fc/fv from the joints' <dynamics friction damping>;
/// gravity 9.81. Throws std::invalid_argument naming the file on parse errors or missing items.
Truth truthFromUrdf(const std::string& path);

/// The <limit> of the URDF's hip and knee joints (index 0 hip, 1 knee): the rig's own limits.
struct UrdfJointLimits {
  std::array<double, 2> lower_rad{}, upper_rad{}, effort_Nm{}, velocity_radps{};
};
/// Throws std::invalid_argument naming the file and joint when a <limit> is missing or empty.
UrdfJointLimits urdfJointLimits(const std::string& path);

/// Effective X at knee angle q2 with the passive bodies lumped: the cylinder rigidly into the
/// thigh and the rod rigidly into the shank, both frozen in the pose the closure gives at q2.
/// This keeps their mass, COM and rotational inertia and neglects the terms from their motion
/// relative to the links (the rod's slide and the cylinder's swing velocity/acceleration), which
/// no 2-link model can hold. Friction as in rigidTruth.
ParamArray lumpedParams(const LegModel& leg, const FourBar& fb, mjData* scratch, double q2);

struct ParamBand {
  ParamArray min{}, max{};
  double q2_min_rad = 0.0, q2_max_rad = 0.0;
  int samples = 0;
};
/// min/max of lumpedParams over n >= 2 evenly spaced knee angles in [q2_min, q2_max].
ParamBand lumpedBand(const LegModel& leg, double q2_min, double q2_max, int n);

}  // namespace exoid::sim

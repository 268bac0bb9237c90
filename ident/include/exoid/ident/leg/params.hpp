#pragma once
// The paper's 10-parameter vector X, defined once: order, names, units, and the
// physical link parameters -> X conversion (paper Eq. 1, corrected; see docs/paper.md).
#include <Eigen/Core>

#include <array>
#include <string>
#include <string_view>

namespace exoid::ident {

inline constexpr int kNumParams = 10;
/// X = [Mxt, Myt, Jt, fc1, fv1, Mxs, Mys, Js, fc2, fv2]; indices 0-4 belong to the hip
/// equation's own columns (thigh), 5-9 to the shank/knee.
enum Param : int { kMxt = 0, kMyt, kJt, kFc1, kFv1, kMxs, kMys, kJs, kFc2, kFv2 };
inline constexpr int kThighFirst = 0;  ///< first of the 5 hip-only parameters
inline constexpr int kShankFirst = 5;  ///< first of the 5 shank (knee) parameters
inline constexpr int kGroupSize = 5;

using ParamVector = Eigen::Matrix<double, kNumParams, 1>;

struct ParamInfo {
  const char* name;     ///< e.g. "Mxt"
  const char* unit;     ///< SI unit, e.g. "kg m"
  const char* meaning;  ///< one line
};

/// Name, unit and meaning of each parameter, in the paper's order.
const std::array<ParamInfo, kNumParams>& paramInfo();
/// The optional 11th parameter: the knee's armature Ia2 (kg m^2), the reflected rotor/actuator
/// inertia on the knee's own diagonal (Khalil's Ia, MuJoCo's armature). It enters the knee
/// equation only, as Ia2 qdd2 (qdd2 = the knee's relative acceleration), so M22 = Js + Ia2 while
/// M12 keeps Js: a geared motor or a hydraulic piston's moving mass. Its index in estimates that
/// carry it (after the 10 of X).
inline constexpr int kKneeArmature = 10;
const ParamInfo& kneeArmatureInfo();  ///< {"Ia2", "kg m^2", ...}

/// "Mxt" ... "fv2"; "Ia2" for kKneeArmature.
std::string_view paramName(int index);
/// Index of a parameter name (case-sensitive), or -1 if unknown.
int paramIndex(std::string_view name);

/// One rigid link in the paper's 2D description (Fig. 2).
struct LinkParams {
  double mass_kg = 0.0;
  double length_m = 0.0;        ///< L: proximal joint to distal joint (used for the thigh only)
  double com_along_m = 0.0;     ///< L - LG: COM distance from the proximal joint along the link
  double com_offset_m = 0.0;    ///< hG: COM offset perpendicular to the link (paper's sign)
  double inertia_com_kgm2 = 0.0;  ///< I: about the COM, axis normal to the sagittal plane
};

/// Physical description of the leg: thigh, shank (+ foot), joint friction.
struct LegPhysical {
  LinkParams thigh;
  LinkParams shank;
  double fc_hip_Nm = 0.0, fv_hip_Nms = 0.0;    ///< Coulomb, viscous (N m s/rad)
  double fc_knee_Nm = 0.0, fv_knee_Nms = 0.0;
};

/// Physical parameters -> X (paper Eq. 1 with the +h^2 sign fix; the print has -h^2).
/// Throws std::invalid_argument for a negative mass or inertia.
ParamVector toParamVector(const LegPhysical& leg);

/// The recommended default truth ("set B" in paper.md): Lt 0.45 m, thigh 13 kg, ...
LegPhysical defaultLeg();

}  // namespace exoid::ident

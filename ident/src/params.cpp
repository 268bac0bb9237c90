#include "exoid/ident/params.hpp"

#include <cmath>
#include <stdexcept>

namespace exoid::ident {

const std::array<ParamInfo, kNumParams>& paramInfo() {
  static const std::array<ParamInfo, kNumParams> info = {{
      {"Mxt", "kg m", "thigh first moment along the link, incl. shank mass at the knee"},
      {"Myt", "kg m", "thigh first moment perpendicular to the link"},
      {"Jt", "kg m^2", "hip-axis inertia of thigh + shank (shank at the knee, Js included)"},
      {"fc1", "N m", "hip Coulomb friction"},
      {"fv1", "N m s/rad", "hip viscous friction"},
      {"Mxs", "kg m", "shank first moment along the link"},
      {"Mys", "kg m", "shank first moment perpendicular to the link"},
      {"Js", "kg m^2", "knee-axis inertia of the shank"},
      {"fc2", "N m", "knee Coulomb friction"},
      {"fv2", "N m s/rad", "knee viscous friction"},
  }};
  return info;
}

const ParamInfo& kneeArmatureInfo() {
  static const ParamInfo info{"Ia2", "kg m^2", "knee armature: reflected rotor/actuator inertia on the knee's diagonal"};
  return info;
}

std::string_view paramName(int index) {
  if (index == kKneeArmature) return kneeArmatureInfo().name;
  if (index < 0 || index >= kNumParams) {
    throw std::invalid_argument("parameter index must be in [0, 10], got " + std::to_string(index));
  }
  return paramInfo()[static_cast<std::size_t>(index)].name;
}

int paramIndex(std::string_view name) {
  for (int i = 0; i < kNumParams; ++i) {
    if (name == paramInfo()[static_cast<std::size_t>(i)].name) return i;
  }
  return -1;
}

namespace {
void checkLink(const LinkParams& l, const char* which) {
  if (!(l.mass_kg >= 0.0) || !(l.inertia_com_kgm2 >= 0.0) || !std::isfinite(l.mass_kg) ||
      !std::isfinite(l.inertia_com_kgm2) || !std::isfinite(l.com_along_m) ||
      !std::isfinite(l.com_offset_m) || !std::isfinite(l.length_m)) {
    throw std::invalid_argument(std::string(which) +
                                ": mass and inertia must be finite and non-negative, got mass " +
                                std::to_string(l.mass_kg) + " kg, inertia " +
                                std::to_string(l.inertia_com_kgm2) + " kg m^2");
  }
}
}  // namespace

ParamVector toParamVector(const LegPhysical& leg) {
  checkLink(leg.thigh, "thigh");
  checkLink(leg.shank, "shank");
  const LinkParams& t = leg.thigh;
  const LinkParams& s = leg.shank;
  const double Lt = t.length_m;
  ParamVector x;
  // Paper Eq. 1 prints -h^2 in both inertia terms; the parallel-axis theorem needs +h^2.
  const double Js = s.inertia_com_kgm2 + s.mass_kg * (s.com_along_m * s.com_along_m +
                                                      s.com_offset_m * s.com_offset_m);
  const double Jt = t.inertia_com_kgm2 +
                    t.mass_kg * (t.com_along_m * t.com_along_m + t.com_offset_m * t.com_offset_m) +
                    s.mass_kg * Lt * Lt + Js;
  x[kMxt] = t.mass_kg * t.com_along_m + s.mass_kg * Lt;
  x[kMyt] = t.mass_kg * t.com_offset_m;
  x[kJt] = Jt;
  x[kFc1] = leg.fc_hip_Nm;
  x[kFv1] = leg.fv_hip_Nms;
  x[kMxs] = s.mass_kg * s.com_along_m;
  x[kMys] = s.mass_kg * s.com_offset_m;
  x[kJs] = Js;
  x[kFc2] = leg.fc_knee_Nm;
  x[kFv2] = leg.fv_knee_Nms;
  return x;
}

LegPhysical defaultLeg() {
  LegPhysical leg;
  leg.thigh = {13.0, 0.45, 0.31, 0.20, 0.28};
  leg.shank = {4.0, 0.45, 0.32, -0.08, 0.16};
  leg.fc_hip_Nm = 1.5;
  leg.fv_hip_Nms = 0.6;
  leg.fc_knee_Nm = 0.35;
  leg.fv_knee_Nms = 0.25;
  return leg;
}

}  // namespace exoid::ident

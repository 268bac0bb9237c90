#include "exoid/ident/leg/params.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/params.hpp"

#include <cmath>
#include <stdexcept>

namespace exoid::ident {

static_assert(kNumParams == core::kNumParams, "ident's X is core's parameter table");

const std::array<ParamInfo, kNumParams>& paramInfo() {
  // Names and units from the one table sim shares (core/params.hpp); what each means, here.
  static const std::array<const char*, kNumParams> kMeaning = {
      "thigh first moment along the link, incl. shank mass at the knee",
      "thigh first moment perpendicular to the link",
      "hip-axis inertia of thigh + shank (shank at the knee, Js included)",
      "hip Coulomb friction",
      "hip viscous friction",
      "shank first moment along the link",
      "shank first moment perpendicular to the link",
      "knee-axis inertia of the shank",
      "knee Coulomb friction",
      "knee viscous friction",
  };
  static const std::array<ParamInfo, kNumParams> info = [] {
    std::array<ParamInfo, kNumParams> out{};
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = {core::kParams[i].name, core::kParams[i].unit, kMeaning[i]};
    return out;
  }();
  return info;
}

const ParamInfo& kneeArmatureInfo() {
  static const ParamInfo info{"Ia2", "kg m^2", "knee armature: reflected rotor/actuator inertia on the knee's diagonal"};
  return info;
}

std::string_view paramName(int index) {
  if (index == kKneeArmature) return kneeArmatureInfo().name;
  if (index < 0 || index >= kNumParams) {
    throw std::invalid_argument("parameter index must be in [0, 10], got " + core::toText(index));
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
                                core::toText(l.mass_kg) + " kg, inertia " +
                                core::toText(l.inertia_com_kgm2) + " kg m^2");
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

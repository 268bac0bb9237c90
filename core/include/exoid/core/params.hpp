#pragma once
// The 10 dynamic parameters X of the 2-link leg, in order, with their SI units: the one table
// ident (identification) and sim (ground truth) both index by position.
#include <array>

namespace exoid::core {

inline constexpr int kNumParams = 10;

struct ParamNameUnit {
  const char* name;
  const char* unit;
};

inline constexpr std::array<ParamNameUnit, kNumParams> kParams{{
    {"Mxt", "kg m"},
    {"Myt", "kg m"},
    {"Jt", "kg m^2"},
    {"fc1", "N m"},
    {"fv1", "N m s/rad"},
    {"Mxs", "kg m"},
    {"Mys", "kg m"},
    {"Js", "kg m^2"},
    {"fc2", "N m"},
    {"fv2", "N m s/rad"},
}};

}  // namespace exoid::core

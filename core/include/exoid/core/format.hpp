#pragma once
// Numbers as text, one way everywhere: in messages, reports and tables. (std::to_string prints a
// double with six fixed decimals: -1e-9 becomes "-0.000000", 1e-300 "0.000000".)
#include <string>
#include <type_traits>

namespace exoid::core {

/// v with `significant` significant digits, shortest form ("%.*g"): 0.5, 1e-09, -1e-09, 2.5e+300,
/// "nan", "inf". 17 digits round-trip every double.
std::string formatNumber(double v, int significant = 6);
/// v with exactly `decimals` digits after the point ("%.*f"), for aligned tables.
std::string formatFixed(double v, int decimals);

/// Names in a message: "hip, knee, ankle" (or with another separator); any container of strings.
template <typename Names>
std::string joined(const Names& names, const char* separator = ", ") {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : separator) + n;
  return out;
}

/// Any number as text: integers exactly, floating point by formatNumber.
template <typename T>
std::string toText(T v) {
  static_assert(std::is_arithmetic_v<T>, "toText takes numbers");
  if constexpr (std::is_floating_point_v<T>) {
    return formatNumber(static_cast<double>(v));
  } else {
    return std::to_string(v);
  }
}

}  // namespace exoid::core

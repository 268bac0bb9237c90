#include "exoid/core/tree_selection.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace exoid::core {

std::string ChainSelection::options() const {
  std::string s;
  const auto add = [&s](const std::string& part) { s += (s.empty() ? "" : " ") + part; };
  if (!base.empty()) add("--base " + base);
  if (!tip.empty()) add("--tip " + tip);
  for (const auto& [joint, value] : locks) {
    char digits[32];  // the shortest text that reads back as the same double: a lock's posture exactly
    const std::to_chars_result r = std::to_chars(digits, digits + sizeof digits, value);
    add("--lock " + joint + "=" + std::string(digits, r.ptr));
  }
  return s;
}

void ChainSelection::addLock(const std::string& s) {
  const auto eq = s.find('=');
  const std::string value = eq == std::string::npos ? "" : s.substr(eq + 1);
  char* end = nullptr;
  const double v = value.empty() ? NAN : std::strtod(value.c_str(), &end);
  if (eq == 0 || eq == std::string::npos || !std::isfinite(v) || *end != '\0') {
    throw std::invalid_argument("expected JOINT=VALUE (the joint held at VALUE rad, or m for a prismatic joint), got '" + s + "'");
  }
  if (!locks.emplace(s.substr(0, eq), v).second) throw std::invalid_argument("joint '" + s.substr(0, eq) + "' is locked twice");
}

}  // namespace exoid::core

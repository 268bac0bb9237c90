#include "exoid/core/tree_selection.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>

namespace exoid::core {

namespace {

// A name as one word of the options' text: quoted (std::quoted) when it holds a space or a quote.
std::string word(const std::string& name) {
  if (name.find_first_of(" \t\n\"\\") == std::string::npos) return name;
  std::ostringstream out;
  out << std::quoted(name);
  return out.str();
}

}  // namespace

std::string ChainSelection::options() const {
  std::string s;
  const auto add = [&s](const std::string& part) { s += (s.empty() ? "" : " ") + part; };
  if (!base.empty()) add("--base " + word(base));
  if (!tip.empty()) add("--tip " + word(tip));
  for (const auto& [joint, value] : locks) {
    char digits[32];  // the shortest text that reads back as the same double: a lock's posture exactly
    const std::to_chars_result r = std::to_chars(digits, digits + sizeof digits, value);
    add("--lock " + word(joint + "=" + std::string(digits, r.ptr)));
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

ChainSelection parseChainSelection(const std::string& text) {
  ChainSelection s;
  if (text == "none") return s;
  std::istringstream in(text);
  std::string option, value;
  while (in >> option) {
    if (!(in >> std::quoted(value))) throw std::invalid_argument("chain selection '" + text + "': " + option + " without a value");
    if (option == "--base") {
      s.base = value;
    } else if (option == "--tip") {
      s.tip = value;
    } else if (option == "--lock") {
      s.addLock(value);
    } else {
      throw std::invalid_argument("chain selection '" + text + "': expected --base, --tip or --lock, got '" + option + "'");
    }
  }
  return s;
}

}  // namespace exoid::core

#include "exoid/experiments/report/cells.hpp"

#include "exoid/experiments/report/table.hpp"

#include <cmath>

namespace exoid::experiments {

std::string csvNumber(double v) { return std::isfinite(v) ? fmt(v, 10) : std::string(); }

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

nlohmann::json jsonNumber(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace exoid::experiments

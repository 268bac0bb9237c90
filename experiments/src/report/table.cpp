#include "exoid/experiments/report/table.hpp"

#include "exoid/core/format.hpp"

#include <algorithm>
#include <cstdio>

namespace exoid::experiments {

void TextTable::print(std::ostream& out) const {
  std::vector<std::size_t> w(header_.size(), 0);
  auto widen = [&](const std::vector<std::string>& r) {
    for (std::size_t c = 0; c < r.size() && c < w.size(); ++c) w[c] = std::max(w[c], r[c].size());
  };
  widen(header_);
  for (const auto& r : rows_) widen(r);
  auto line = [&](const std::vector<std::string>& r) {
    for (std::size_t c = 0; c < w.size(); ++c) {
      const std::string cell = c < r.size() ? r[c] : "";
      out << (c ? "  " : "") << cell << std::string(w[c] - cell.size(), ' ');
    }
    out << '\n';
  };
  line(header_);
  std::size_t total = 0;
  for (std::size_t c = 0; c < w.size(); ++c) total += w[c] + (c ? 2 : 0);
  out << std::string(total, '-') << '\n';
  for (const auto& r : rows_) line(r);
}

void TextTable::printMarkdown(std::ostream& out) const {
  // A '|' inside a cell (e.g. "|error|") would split the column: escaped as GitHub tables expect.
  auto cell = [](const std::string& s) {
    std::string e;
    for (char ch : s) e += ch == '|' ? std::string("\\|") : std::string(1, ch);
    return e;
  };
  auto line = [&](const std::vector<std::string>& r) {
    out << '|';
    for (std::size_t c = 0; c < header_.size(); ++c) out << ' ' << (c < r.size() ? cell(r[c]) : "") << " |";
    out << '\n';
  };
  line(header_);
  out << '|';
  for (std::size_t c = 0; c < header_.size(); ++c) out << "---|";
  out << '\n';
  for (const auto& r : rows_) line(r);
}

std::string fmt(double v, int significant) { return core::formatNumber(v, significant); }
std::string fixed(double v, int decimals) {
  std::string s = core::formatFixed(v, decimals);
  // A value that rounds to zero is 0, not "-0.00" (a tiny negative gap read as a sign).
  if (s.size() > 1 && s[0] == '-' && s.find_first_not_of("0.", 1) == std::string::npos) s.erase(0, 1);
  return s;
}
bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace exoid::experiments

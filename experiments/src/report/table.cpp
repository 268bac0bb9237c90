#include "exoid/experiments/report/table.hpp"

#include "exoid/core/format.hpp"

#include <algorithm>
#include <cstdio>

namespace exoid::experiments {

std::string wrapped(const std::string& original, std::size_t width, std::size_t indent) {
  // Never inside "12 N m": the number and its unit are one word (kNoBreak, a space after wrapping).
  std::string text = original;
  for (std::size_t at = text.find(" N m"); at != std::string::npos; at = text.find(" N m", at + 1)) text[at] = text[at + 2] = kNoBreak;
  std::string out, line;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    start = end + 1;
    // A word of one or two characters ("m", "%)") stays with the one before it (units, not orphans).
    if (!line.empty() && line.size() + 1 + word.size() > width && (word.size() > 2 || line.size() >= width)) {
      out += line + '\n';
      line = std::string(indent, ' ');
    }
    line += (line.empty() || line.back() == ' ' ? "" : " ") + word;
  }
  out += line;
  std::replace(out.begin(), out.end(), kNoBreak, ' ');
  return out;
}

void printCombinations(std::ostream& out, const std::vector<std::string>& labels, const std::vector<std::string>& combinations) {
  bool any = false;
  for (std::size_t i = 0; i < labels.size() && i < combinations.size(); ++i) {
    if (labels[i] == combinations[i]) continue;
    if (!any) out << "where (each base parameter that regroups others, written out):\n";
    any = true;
    // Lines break between terms only: a term ("- 0.45 shank.m") keeps its sign and coefficient.
    const char kGlue = kNoBreak;
    std::string text = labels[i] + " = " + combinations[i];
    for (std::size_t k = 0; k < text.size(); ++k) {
      const bool term_starts = k + 2 < text.size() && (text[k + 1] == '+' || text[k + 1] == '-' || text[k + 1] == '=') && text[k + 2] == ' ';
      if (text[k] == ' ' && !term_starts) text[k] = kGlue;
    }
    out << wrapped(text) << '\n';
  }
}

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

#pragma once
// Plain-text tables for stdout.
#include <ostream>
#include <string>
#include <vector>

namespace exoid::experiments {

class TextTable {
 public:
  explicit TextTable(std::vector<std::string> header) : header_(std::move(header)) {}
  void addRow(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  void print(std::ostream& out) const;
  /// GitHub markdown table.
  void printMarkdown(std::ostream& out) const;

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

/// printf-style "%.*g" of a double.
/// A space that wrapped() never breaks at (written as a space): "0.45\x1fshank.m".
inline constexpr char kNoBreak = '\x1f';
/// `text` broken at spaces into lines of at most `width` characters (a longer word stands alone; a
/// word of one or two characters, a unit, stays on its predecessor's line: up to width + 3), the
/// later lines indented by `indent` spaces; lines joined by '\n', no trailing newline; never inside
/// "N m" nor at a kNoBreak. The
/// default keeps every line within a 120-column terminal.
std::string wrapped(const std::string& text, std::size_t width = 117, std::size_t indent = 4);
/// Below a table of base parameters by label: each label that stands for a combination of
/// standard parameters, written out once ("label = combination"), wrapped at 120 characters.
void printCombinations(std::ostream& out, const std::vector<std::string>& labels, const std::vector<std::string>& combinations);

std::string fmt(double v, int significant = 5);
/// Fixed decimals, "%.*f".
std::string fixed(double v, int decimals = 4);
/// Whether s ends with suffix (case-sensitive), e.g. a file name's extension.
bool endsWith(const std::string& s, const std::string& suffix);

}  // namespace exoid::experiments

#include "csv_lines.hpp"

namespace exoid::ident::csv {

std::string_view trimBlanks(std::string_view s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

void LineSplitter::splitCells(std::string_view line, long line_no) {
  std::vector<std::string_view>& cells = line_.cells;
  unquoted_.clear();
  std::size_t i = 0;
  while (true) {
    // Blanks before an opening quote are tolerated (some writers pad).
    std::size_t j = i;
    while (j < line.size() && (line[j] == ' ' || line[j] == '\t')) ++j;
    if (j < line.size() && line[j] == '"') {
      const std::size_t open = j + 1;
      std::size_t k = open;
      bool closed = false, escaped = false;
      while (k < line.size()) {
        if (line[k] == '"') {
          if (k + 1 < line.size() && line[k + 1] == '"') {
            escaped = true;
            k += 2;
            continue;
          }
          closed = true;
          break;
        }
        ++k;
      }
      if (!closed) {
        throw SyntaxError{line_no, static_cast<long>(cells.size()) + 1,
                          "unclosed double quote (a quoted cell must end on the same line)"};
      }
      std::string_view cell = line.substr(open, k - open);
      if (escaped) {
        std::string u;
        for (std::size_t m = 0; m < cell.size(); ++m) {
          u += cell[m];
          if (cell[m] == '"') ++m;  // "" -> "
        }
        unquoted_.push_back(std::move(u));
      }
      ++k;  // past the closing quote
      while (k < line.size() && (line[k] == ' ' || line[k] == '\t')) ++k;
      if (k < line.size() && line[k] != ',') {
        throw SyntaxError{line_no, static_cast<long>(cells.size()) + 1, "text after the closing double quote of a cell"};
      }
      cells.push_back(escaped ? std::string_view(unquoted_.back()) : cell);
      if (k >= line.size()) break;
      i = k + 1;
      continue;
    }
    const auto comma = line.find(',', i);
    cells.push_back(line.substr(i, comma == std::string_view::npos ? std::string_view::npos : comma - i));
    if (comma == std::string_view::npos) break;
    i = comma + 1;
  }
}

}  // namespace exoid::ident::csv

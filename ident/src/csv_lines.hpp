#pragma once
// Internal to the dataset reader: a CSV text as lab tools write it, split into lines and cells.
// Lines end in LF, CRLF or CR alone; a UTF-8 byte-order mark is skipped; cells follow RFC 4180
// (a cell in double quotes may hold commas, and "" stands for one quote). Blank lines are dropped;
// lines starting with '#' are comments.
#include <string>
#include <string_view>
#include <vector>

namespace exoid::ident::csv {

struct Line {
  long number = 0;                 ///< 1-based line number in the file
  bool comment = false;            ///< starts with '#' (after leading blanks)
  std::string text;                ///< the comment without '#', or empty
  std::vector<std::string> cells;  ///< unquoted, not trimmed
};

/// Thrown for a malformed cell (an unclosed quote, text after a closing quote).
struct SyntaxError {
  long line = 0, column = 0;  ///< 1-based; column = cell index
  std::string what;
};

/// Calls visit(line) for each non-blank line of `text`, in order, reusing one Line (so a long
/// log is never held as cells). Throws SyntaxError.
template <typename Visit>
void forEachLine(std::string_view text, Visit&& visit);

/// RFC 4180 cells of one line (no line breaks inside) into `cells`. Throws SyntaxError.
void splitCells(std::string_view line, long line_no, std::vector<std::string>& cells);

/// Leading and trailing blanks (space, tab) removed.
std::string_view trimBlanks(std::string_view s);

template <typename Visit>
void forEachLine(std::string_view text, Visit&& visit) {
  if (text.size() >= 3 && static_cast<unsigned char>(text[0]) == 0xEF && static_cast<unsigned char>(text[1]) == 0xBB &&
      static_cast<unsigned char>(text[2]) == 0xBF) {
    text.remove_prefix(3);  // UTF-8 byte-order mark (Excel's "CSV UTF-8")
  }
  Line line;
  long number = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find_first_of("\r\n", pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view raw = text.substr(pos, end - pos);
    ++number;
    pos = end;
    if (pos < text.size()) pos += (text[pos] == '\r' && pos + 1 < text.size() && text[pos + 1] == '\n') ? 2 : 1;
    const std::string_view t = trimBlanks(raw);
    if (t.empty()) continue;
    line.number = number;
    line.comment = t[0] == '#';
    line.text.clear();
    if (line.comment) {
      line.text.assign(t.substr(1));
      line.cells.clear();
    } else {
      splitCells(raw, number, line.cells);
    }
    visit(line);
  }
}

}  // namespace exoid::ident::csv

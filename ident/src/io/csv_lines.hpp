#pragma once
// Internal to the dataset reader: a CSV text as lab tools write it, split into lines and cells,
// streamed chunk by chunk (a long log is never held whole). Lines end in LF, CRLF or CR alone; a
// UTF-8 byte-order mark is skipped; cells follow RFC 4180 (a cell in double quotes may hold
// commas, and "" stands for one quote). Blank lines are dropped; lines starting with '#' are
// comments.
#include <cerrno>
#include <cstddef>
#include <cstring>
#include <deque>
#include <istream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace exoid::ident::csv {

struct Line {
  long number = 0;                      ///< 1-based line number in the file
  bool comment = false;                 ///< starts with '#' (after leading blanks)
  std::string_view text;                ///< the comment without '#'
  std::vector<std::string_view> cells;  ///< unquoted, not trimmed; valid during the visit only
};

/// Thrown for a malformed cell (an unclosed quote, text after a closing quote).
struct SyntaxError {
  long line = 0, column = 0;  ///< 1-based; column = cell index
  std::string what;
};

/// Leading and trailing blanks (space, tab) removed.
std::string_view trimBlanks(std::string_view s);

/// Splits the text a `read` function supplies (read(buffer) appends the next chunk and returns
/// false at the end) into lines and calls visit(line) for each non-blank one, in order. With
/// split_cells false, data lines come without cells (a fast counting pass). Throws SyntaxError.
class LineSplitter {
 public:
  template <typename Read, typename Visit>
  void run(Read&& read, Visit&& visit, bool split_cells = true);

 private:
  void splitCells(std::string_view line, long line_no);
  Line line_;
  std::deque<std::string> unquoted_;  // quoted cells with "" escapes, unescaped (stable addresses)
};

/// Chunks of a stream, 1 MiB at a time.
/// Appends up to 1 MiB of `in` to buffer; false at the end of the stream. A failed read (an I/O
/// error, a folder given as a file) is not an end: it throws std::runtime_error, so a log is never
/// silently cut short.
inline bool readChunk(std::istream& in, std::string& buffer) {
  constexpr std::size_t kChunk = 1 << 20;
  const std::size_t old = buffer.size();
  buffer.resize(old + kChunk);
  errno = 0;
  in.read(buffer.data() + old, static_cast<std::streamsize>(kChunk));
  buffer.resize(old + static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw std::runtime_error(std::string("reading failed") + (errno != 0 ? std::string(": ") + std::strerror(errno) : ""));
  return in.gcount() > 0;
}

template <typename Read, typename Visit>
void LineSplitter::run(Read&& read, Visit&& visit, bool split_cells) {
  std::string buf;
  std::size_t pos = 0;
  long number = 0;
  bool eof = false, first = true;
  char eol = 0;  // '\n' (LF and CRLF files) or '\r' (CR-only), from the first line end seen
  const auto lineEnd = [&](std::size_t from) -> std::size_t {
    if (!eol) {
      const std::size_t lf = buf.find('\n', from), cr = buf.find('\r', from);
      if (lf == std::string::npos && cr == std::string::npos) return std::string::npos;
      eol = lf != std::string::npos ? '\n' : '\r';
    }
    const void* hit = std::memchr(buf.data() + from, eol, buf.size() - from);  // memchr: the hot loop
    if (!hit) return std::string::npos;
    std::size_t e = static_cast<std::size_t>(static_cast<const char*>(hit) - buf.data());
    if (eol == '\n' && e > from && buf[e - 1] == '\r') --e;  // CRLF
    return e;
  };
  while (true) {
    // Refill when no complete line is left (a CR at the very end may be half of a CRLF).
    std::size_t end = pos < buf.size() ? lineEnd(pos) : std::string::npos;
    if (!eof && (end == std::string::npos || end + 1 >= buf.size())) {
      buf.erase(0, pos);
      pos = 0;
      eof = !read(buf);
      if (first && buf.size() >= 3 && static_cast<unsigned char>(buf[0]) == 0xEF &&
          static_cast<unsigned char>(buf[1]) == 0xBB && static_cast<unsigned char>(buf[2]) == 0xBF) {
        pos = 3;  // UTF-8 byte-order mark (Excel's "CSV UTF-8")
      }
      first = false;
      continue;
    }
    if (pos >= buf.size()) break;
    if (end == std::string::npos) end = buf.size();
    const std::string_view raw(buf.data() + pos, end - pos);
    ++number;
    pos = end;
    if (pos < buf.size()) pos += (buf[pos] == '\r' && pos + 1 < buf.size() && buf[pos + 1] == '\n') ? 2 : 1;
    const std::string_view t = trimBlanks(raw);
    if (t.empty()) continue;
    line_.number = number;
    line_.comment = t[0] == '#';
    line_.cells.clear();
    if (line_.comment) {
      line_.text = t.substr(1);
    } else {
      line_.text = {};
      if (split_cells) splitCells(raw, number);
    }
    visit(line_);
  }
}

}  // namespace exoid::ident::csv

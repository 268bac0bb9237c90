#pragma once
// Internal to the dataset reader: a CSV text as lab tools write it, split into lines and cells,
// streamed chunk by chunk (a long log is never held whole). Lines end in LF, CRLF or CR alone; a
// UTF-8 byte-order mark is skipped; cells follow RFC 4180 (a cell in double quotes may hold
// commas, and "" stands for one quote). Blank lines are dropped; lines starting with '#' are
// comments.
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <algorithm>
#include <deque>
#include <istream>
#include <memory>
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
  std::int64_t offset = 0;              ///< byte offset of the line's first character in the text read
};

/// Where a run starts: the text's beginning, or a line that an earlier run over the same text
/// visited (its offset, and the file's line number and line end from that run), so that several
/// runs over consecutive ranges of one file see every line as a single run would.
struct Start {
  long line_number = 1;  ///< number of the first line read
  char eol = 0;          ///< '\n' or '\r' when known; 0: from the first line end seen
  bool at_file_start = true;  ///< a UTF-8 byte-order mark is skipped only here
  std::size_t bytes = std::size_t(-1);  ///< the text's length when known (a short one: a small buffer)
};

/// Thrown for a malformed cell (an unclosed quote, text after a closing quote).
struct SyntaxError {
  long line = 0, column = 0;  ///< 1-based; column = cell index
  std::string what;
};

/// Leading and trailing blanks (space, tab) removed.
std::string_view trimBlanks(std::string_view s);

/// Splits the text a `read` function supplies (read(dst, max) writes up to max bytes of the next
/// chunk to dst and returns how many, 0 at the end) into lines and calls visit(line) for each
/// non-blank one, in order. With split_cells false, data lines come without cells (a fast
/// counting pass). Throws SyntaxError.
class LineSplitter {
 public:
  template <typename Read, typename Visit>
  void run(Read&& read, Visit&& visit, bool split_cells = true, const Start& start = {});
  /// During a run: split the lines after this one into cells or not (e.g. the header only).
  /// The line end of the text run last ('\n' for LF and CRLF, '\r' for CR alone; 0: none seen).
  char eol() const { return eol_; }
  /// During a run: no line after this one is visited (the run returns).
  void stop() { stop_ = true; }
  /// Lines the last run went through, blank ones included.
  long lines() const { return lines_; }

 private:
  void splitCells(std::string_view line, long line_no);
  /// Room for `more` bytes after the first `keep` of the buffer (which stay).
  char* reserve(std::size_t keep, std::size_t more);
  Line line_;
  bool split_cells_ = true;
  bool stop_ = false;
  char eol_ = 0;
  long lines_ = 0;
  std::unique_ptr<char[]> buf_;  // not zero-filled: every byte used is read into it first
  std::size_t capacity_ = 0;
  std::deque<std::string> unquoted_;  // quoted cells with "" escapes, unescaped (stable addresses)
};

inline constexpr std::size_t kChunkBytes = std::size_t(1) << 20;

/// Reads up to max bytes of `in` into dst and returns how many (0: the end of the stream). A
/// failed read (an I/O error, a folder given as a file) is not an end: it throws
/// std::runtime_error, so a log is never silently cut short.
inline std::size_t readChunk(std::istream& in, char* dst, std::size_t max) {
  errno = 0;
  in.read(dst, static_cast<std::streamsize>(max));
  if (in.bad()) throw std::runtime_error(std::string("reading failed") + (errno != 0 ? std::string(": ") + std::strerror(errno) : ""));
  return static_cast<std::size_t>(in.gcount());
}

inline char* LineSplitter::reserve(std::size_t keep, std::size_t more) {
  if (keep + more > capacity_) {
    const std::size_t capacity = std::max(2 * capacity_, keep + more);
    std::unique_ptr<char[]> bigger(new char[capacity]);
    if (keep > 0) std::memcpy(bigger.get(), buf_.get(), keep);
    buf_ = std::move(bigger);
    capacity_ = capacity;
  }
  return buf_.get();
}

template <typename Read, typename Visit>
void LineSplitter::run(Read&& read, Visit&& visit, bool split_cells, const Start& start) {
  const std::size_t chunk = std::min(kChunkBytes, start.bytes == std::size_t(-1) ? kChunkBytes : start.bytes + 1);
  char* buf = reserve(0, chunk);
  std::size_t size = 0, pos = 0;
  std::int64_t consumed = 0;  // bytes of the text moved out of the front of buf
  long number = start.line_number - 1;
  bool eof = false, first = start.at_file_start;
  char& eol = eol_;  // '\n' (LF and CRLF files) or '\r' (CR-only), from the first line end seen
  eol = start.eol;
  split_cells_ = split_cells;
  stop_ = false;
  const auto lineEnd = [&](std::size_t from) -> std::size_t {
    if (!eol) {
      const std::string_view text(buf, size);
      const std::size_t lf = text.find('\n', from), cr = text.find('\r', from);
      if (lf == std::string_view::npos && cr == std::string_view::npos) return std::string_view::npos;
      eol = lf != std::string_view::npos ? '\n' : '\r';
    }
    const void* hit = std::memchr(buf + from, eol, size - from);  // memchr: the hot loop
    if (!hit) return std::string_view::npos;
    std::size_t e = static_cast<std::size_t>(static_cast<const char*>(hit) - buf);
    if (eol == '\n' && e > from && buf[e - 1] == '\r') --e;  // CRLF
    return e;
  };
  while (true) {
    // Refill when no complete line is left (a CR at the very end may be half of a CRLF).
    std::size_t end = pos < size ? lineEnd(pos) : std::string_view::npos;
    if (!eof && (end == std::string_view::npos || end + 1 >= size)) {
      if (pos > 0) std::memmove(buf, buf + pos, size - pos);
      size -= pos;
      consumed += static_cast<std::int64_t>(pos);
      pos = 0;
      buf = reserve(size, chunk);
      const std::size_t got = read(buf + size, chunk);
      size += got;
      eof = got == 0;
      if (first && size >= 3 && static_cast<unsigned char>(buf[0]) == 0xEF && static_cast<unsigned char>(buf[1]) == 0xBB &&
          static_cast<unsigned char>(buf[2]) == 0xBF) {
        pos = 3;  // UTF-8 byte-order mark (Excel's "CSV UTF-8")
      }
      first = false;
      continue;
    }
    if (pos >= size) break;
    if (end == std::string_view::npos) end = size;
    const std::string_view raw(buf + pos, end - pos);
    const std::int64_t offset = consumed + static_cast<std::int64_t>(pos);
    ++number;
    pos = end;
    if (pos < size) pos += (buf[pos] == '\r' && pos + 1 < size && buf[pos + 1] == '\n') ? 2 : 1;
    // Blank, a comment or data, from the first character that is not a blank (the whole trim is
    // for comments only: a data line's cells are trimmed one by one).
    std::size_t lead = 0;
    while (lead < raw.size() && (raw[lead] == ' ' || raw[lead] == '\t')) ++lead;
    if (lead == raw.size()) continue;
    line_.number = number;
    line_.offset = offset;
    line_.comment = raw[lead] == '#';
    line_.cells.clear();
    if (line_.comment) {
      line_.text = trimBlanks(raw).substr(1);
    } else {
      line_.text = {};
      if (split_cells_) splitCells(raw, number);
    }
    visit(line_);
    if (stop_) break;
  }
  lines_ = number - (start.line_number - 1);
}

}  // namespace exoid::ident::csv

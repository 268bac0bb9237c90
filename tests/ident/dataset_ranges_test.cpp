// The reader cuts a log's data rows into ranges parsed in parallel: whatever the range size and
// the number of threads, the dataset is the one a single pass reads, and an error is the first in
// the file (its line and column).
#include "exoid/ident/io/dataset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>

#include <sys/stat.h>
#include <unistd.h>

namespace exoid::ident {
namespace {

// 200 rows at 1 kHz with what lab tools write: a byte-order mark, comments before and among the
// rows, blank lines, a trailing comma, a numeric extra column and one that turns to text late.
std::string labLog(const std::string& eol) {
  std::string s = "\xEF\xBB\xBF# rig: test" + eol + "t,q_hip,q_knee,tau_hip,tau_knee,temp,mode," + eol;
  for (int i = 0; i < 200; ++i) {
    if (i % 37 == 5) s += "# note at row " + std::to_string(i) + eol;
    if (i % 53 == 9) s += "  " + eol;
    char row[200];
    std::snprintf(row, sizeof row, "%.17g,%.17g,%.17g,%.17g,%.17g,%.3f,%s,", 0.001 * i, 0.5 * std::sin(0.01 * i), 1.0 + 0.001 * i,
                  2.0 - 0.01 * i, -0.5 * i, 36.5 + 0.01 * i, i < 170 ? "1" : "RUN");
    s += row + eol;
  }
  return s + "# end" + eol;
}

void expectSameDataset(const Dataset& a, const Dataset& b) {
  EXPECT_EQ(a.t_s, b.t_s);
  EXPECT_EQ(a.q_rad, b.q_rad);
  EXPECT_EQ(a.tau_Nm, b.tau_Nm);
  EXPECT_EQ(a.extra, b.extra);
  EXPECT_EQ(a.extra_names, b.extra_names);
  EXPECT_EQ(a.text_columns, b.text_columns);
  EXPECT_EQ(a.comments, b.comments);
  EXPECT_EQ(a.sampling.rows_read, b.sampling.rows_read);
  EXPECT_EQ(a.sampling.max_dt_line, b.sampling.max_dt_line);
}

CsvReadOptions inRanges(std::size_t bytes, int threads) {
  CsvReadOptions o;
  o.range_bytes = bytes;
  o.threads = threads;
  return o;
}

// The reader's DatasetError message for this text, or "" when it reads.
std::string readError(std::string_view text, const CsvReadOptions& o = {}) {
  try {
    parseDatasetText(text, "log.csv", o);
  } catch (const DatasetError& e) {
    return e.what();
  }
  return "";
}

TEST(DatasetRanges, EveryRangeSizeAndThreadCountReadsTheSameDataset) {
  for (const std::string eol : {"\n", "\r\n", "\r"}) {
    const std::string text = labLog(eol);
    CsvReadOptions whole;
    whole.range_bytes = text.size() + 1;  // one range: a single pass
    whole.threads = 1;
    const Dataset one = parseDatasetText(text, "log.csv", whole);
    ASSERT_EQ(one.size(), 200);
    EXPECT_EQ(one.text_columns, std::vector<std::string>{"mode"});  // text in the last rows only
    EXPECT_EQ(one.extra_names, std::vector<std::string>{"temp"});
    EXPECT_EQ(one.comments.size(), 8u);  // before the header, 6 among the rows, at the end
    for (std::size_t bytes : {std::size_t(1), std::size_t(7), std::size_t(300), std::size_t(4096)}) {
      for (int threads : {1, 3}) {
        SCOPED_TRACE("range " + std::to_string(bytes) + " B, " + std::to_string(threads) + " threads, eol " +
                     std::to_string(static_cast<int>(eol.back())));
        expectSameDataset(parseDatasetText(text, "log.csv", inRanges(bytes, threads)), one);
      }
    }
  }
}

TEST(DatasetRanges, AFileReadInRangesIsTheTextReadWhole) {
  const std::string text = labLog("\r\n");
  const std::string path = (std::filesystem::temp_directory_path() / "exoid_dataset_ranges_test.csv").string();
  std::ofstream(path, std::ios::binary) << text;
  const Dataset from_file = readDatasetCsv(path, inRanges(100, 2));
  std::filesystem::remove(path);
  expectSameDataset(from_file, parseDatasetText(text, path, inRanges(text.size() + 1, 1)));
}

// A file without a size to cut (a pipe, e.g. --data <(zcat log.gz)) is read as a stream.
TEST(DatasetRanges, APipeIsReadWhole) {
  const std::string text = labLog("\n");
  const std::string path = (std::filesystem::temp_directory_path() / ("exoid_dataset_pipe_" + std::to_string(::getpid()))).string();
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  std::thread writer([&] { std::ofstream(path, std::ios::binary) << text; });
  const Dataset from_pipe = readDatasetCsv(path, inRanges(100, 2));
  writer.join();
  std::filesystem::remove(path);
  expectSameDataset(from_pipe, parseDatasetText(text, path, inRanges(text.size() + 1, 1)));
}

TEST(DatasetRanges, TheFirstErrorInTheFileWhateverTheRanges) {
  std::string text = labLog("\n");
  // Two bad cells: tau_hip on the data line 60 and q_knee on the data line 150 (file lines 2 +
  // comments and blanks before them); the first in the file is the one named.
  const auto bad = [&](int row, int cell, const std::string& value) {
    std::size_t at = text.find("\n" + [&] {
      char b[40];
      std::snprintf(b, sizeof b, "%.17g,", 0.001 * row);
      return std::string(b);
    }());
    ASSERT_NE(at, std::string::npos);
    ++at;
    for (int c = 0; c < cell; ++c) at = text.find(',', at) + 1;
    text.replace(at, text.find(',', at) - at, value);
  };
  bad(150, 2, "x");
  bad(60, 3, "oops");
  const std::string single = readError(text, inRanges(text.size() + 1, 1));
  ASSERT_NE(single.find("tau_hip"), std::string::npos) << single;
  for (std::size_t bytes : {std::size_t(1), std::size_t(64), std::size_t(2000)}) {
    for (int threads : {1, 4}) {
      EXPECT_EQ(readError(text, inRanges(bytes, threads)), single) << "a log with two bad cells";
    }
  }
}

// The time axis's errors name the file's line of the offending row (comments and blank lines
// counted), in ranges as whole.
TEST(DatasetRanges, TimeAxisErrorsNameTheFileLineInRangesAsWhole) {
  const auto log = [](double t_at_100, double t_at_101) {
    std::string s = "# a comment\n\nt,q_hip,q_knee,tau_hip,tau_knee\n";  // the header is line 3
    for (int i = 0; i < 150; ++i) {
      if (i == 50) s += "# note\n";  // rows 50.. are one line further down
      const double t = i == 100 ? t_at_100 : i == 101 ? t_at_101 : 0.001 * i + (i > 101 ? 0.05 : 0.0);
      s += std::to_string(t) + ",0.1,0.2,1.5,2.5\n";
    }
    return s;
  };
  struct Case {
    std::string text;
    bool strict;
    std::string expected;  // how the message starts
  };
  const std::vector<Case> cases = {
      {log(0.099, 0.1), false, "log.csv:105:1: time must be strictly increasing"},    // row 100 (t = 0.099 after 0.099)
      {log(0.1, 0.151), false, "log.csv:106:1: a gap of 0.051 s between lines 105 and 106"},  // row 101: 51 ms after row 100
      {log(0.1, 0.101), true, "log.csv:107:1: sampling is not uniform"},           // row 102 jumps by 51 ms
  };
  for (const Case& c : cases) {
    CsvReadOptions o;
    if (c.strict) o.sampling = SamplingMode::kStrict;
    o.range_bytes = c.text.size() + 1;
    const std::string whole = readError(c.text, o);
    EXPECT_EQ(whole.rfind(c.expected, 0), 0u) << whole;
    for (std::size_t bytes : {std::size_t(1), std::size_t(40), std::size_t(700)}) {
      o.range_bytes = bytes;
      o.threads = 2;
      EXPECT_EQ(readError(c.text, o), whole) << c.expected;
    }
  }
}

// Any range size, the largest included, and an empty text.
TEST(DatasetRanges, AnyRangeSizeAndAnEmptyText) {
  const std::string text = labLog("\n");
  const Dataset one = parseDatasetText(text, "log.csv", inRanges(text.size() + 1, 1));
  for (std::size_t bytes : {std::size_t(0), std::numeric_limits<std::size_t>::max(), std::size_t(1) << 63}) {
    expectSameDataset(parseDatasetText(text, "log.csv", inRanges(bytes, 2)), one);
  }
  const std::string empty = readError(std::string_view{});
  EXPECT_NE(empty.find("empty file"), std::string::npos) << "an empty text: " << empty;
}

// A text's line end is decided on all of it, as one pass would: a CR text with one LF past the
// reader's first MiB is read by LF.
TEST(DatasetRanges, ATextsLineEndIsDecidedOnAllOfIt) {
  std::string text = "t,q_hip,q_knee,tau_hip,tau_knee\r";
  while (text.size() < (std::size_t(3) << 19)) text += "0.001,0.1,0.2,1.5,2.5\r";
  const std::string lf = text.substr(0, text.size() - 1) + "\n";
  // One line of LF-separated text: its cells are the header's 5 and every row's.
  const std::string error = readError(lf);
  EXPECT_NE(error.find("log.csv:1:"), std::string::npos) << "a CR file with an LF, read as LF lines: " << error;
}

TEST(DatasetRanges, NegativeThreadsAreRefusedByName) {
  CsvReadOptions o;
  o.threads = -1;
  const std::string error = readError(labLog("\n"), o);
  EXPECT_NE(error.find("'threads' must be >= 0"), std::string::npos) << "threads = -1: " << error;
}

}  // namespace
}  // namespace exoid::ident

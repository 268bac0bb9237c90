// The dataset reader on logs as lab tools write them (every case issue 11 measured being rejected),
// the log format (column map, units, torque signs) and the resampling of jittered timestamps.
#include "exoid/ident/io/dataset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace exoid::ident {
namespace {

// 30 rows of a tiny log, t in s at 1 kHz: q_hip = 0.1 i, tau_knee = -i.
std::string body(const std::string& sep = "\n", const std::string& trail = "") {
  std::string s;
  for (int i = 0; i < 30; ++i) {
    s += std::to_string(0.001 * i) + "," + std::to_string(0.1 * i) + ",0.2,1.5," + std::to_string(-i) + trail + sep;
  }
  return s;
}
const std::string kHeader = "t,q_hip,q_knee,tau_hip,tau_knee";

Dataset parse(const std::string& text, const CsvReadOptions& o = {}) {
  return parseDatasetText(text, "log.csv", o);
}

void expectTinyLog(const Dataset& d) {
  ASSERT_EQ(d.size(), 30);
  EXPECT_DOUBLE_EQ(d.q_rad(7, 0), 0.7);
  EXPECT_DOUBLE_EQ(d.tau_Nm(29, 1), -29.0);
  EXPECT_DOUBLE_EQ(d.t_s[29], 0.029);
}

TEST(DatasetFormats, ByteOrderMarkAndEveryLineEnding) {
  expectTinyLog(parse("\xEF\xBB\xBF" + kHeader + "\n" + body()));
  expectTinyLog(parse(kHeader + "\r\n" + body("\r\n")));
  expectTinyLog(parse(kHeader + "\r" + body("\r")));  // CR alone (classic Mac, some loggers)
}

TEST(DatasetFormats, Rfc4180QuotesInHeaderAndCells) {
  std::string text = "\"t\",\"q_hip\",\"q_knee\",\"tau_hip\",\"tau_knee\",\"note, with comma\"\n";
  for (int i = 0; i < 30; ++i) {
    text += "\"" + std::to_string(0.001 * i) + "\"," + std::to_string(0.1 * i) + ",0.2,1.5," + std::to_string(-i) +
            ",\"said \"\"ok\"\"\"\n";
  }
  const Dataset d = parse(text);
  expectTinyLog(d);
  EXPECT_EQ(d.text_columns, std::vector<std::string>{"note, with comma"});
}

TEST(DatasetFormats, TrailingCommaOnEveryLine) { expectTinyLog(parse(kHeader + ",\n" + body("\n", ","))); }

TEST(DatasetFormats, TextColumnsAreIgnoredNumericOnesKept) {
  std::string text = kHeader + ",mode,temp\n";
  for (int i = 0; i < 30; ++i) text += std::to_string(0.001 * i) + "," + std::to_string(0.1 * i) + ",0.2,1.5," + std::to_string(-i) + ",RUN,36.5\n";
  const Dataset d = parse(text);
  expectTinyLog(d);
  EXPECT_EQ(d.text_columns, std::vector<std::string>{"mode"});
  EXPECT_EQ(d.extra_names, std::vector<std::string>{"temp"});
  EXPECT_THROW(d.extraColumn("mode"), std::invalid_argument);
}

TEST(DatasetFormats, CommentsAnywhereAndBlankLines) {
  const Dataset d = parse("# rig: dfki\n\n" + kHeader + "\n# started\n" + body() + "\n# end\n");
  expectTinyLog(d);
  EXPECT_EQ(d.metadata("rig").value(), "dfki");
  EXPECT_EQ(d.comments.back(), " end");
}

TEST(DatasetFormats, ColumnMapUnitsAndSigns) {
  std::string text = "time_ms,pos1,pos2,eff1,eff2\n";
  for (int i = 0; i < 30; ++i) text += std::to_string(2 * i) + "," + std::to_string(10 * i) + ",90,1.5,2\n";
  CsvReadOptions o;
  o.format.columns = parseColumnMap("t=time_ms, q_hip=pos1,q_knee=pos2,tau_hip=eff1,tau_knee=eff2");
  o.format.time_scale_s = parseTimeUnit("ms");
  o.format.angle_scale_rad = parseAngleUnit("deg");
  o.format.torque_sign = {1.0, -1.0};
  const Dataset d = parse(text, o);
  ASSERT_EQ(d.size(), 30);
  EXPECT_DOUBLE_EQ(d.t_s[1], 0.002);
  EXPECT_DOUBLE_EQ(d.q_rad(3, 0), 30.0 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(d.q_rad(0, 1), M_PI / 2);
  EXPECT_DOUBLE_EQ(d.tau_Nm(0, 1), -2.0);
  // A mapped name the header lacks is named, with what the header has.
  o.format.columns = parseColumnMap("t=time,q_hip=pos1,q_knee=pos2,tau_hip=eff1,tau_knee=eff2");
  try {
    parse(text, o);
    FAIL();
  } catch (const DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find("'time' (mapped to t)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("time_ms"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 1);
  }
  EXPECT_THROW(parseColumnMap("t=time,q_hip"), std::invalid_argument);
  EXPECT_THROW(parseTimeUnit("min"), std::invalid_argument);
  EXPECT_THROW(parseAngleUnit("grad"), std::invalid_argument);
}

TEST(DatasetFormats, MalformedQuotesNameLineAndCell) {
  try {
    parse(kHeader + "\n0,\"0.1,0.2,1,2\n");
    FAIL();
  } catch (const DatasetError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.column(), 2);
    EXPECT_NE(std::string(e.what()).find("unclosed double quote"), std::string::npos) << e.what();
  }
}

// Resampling: a quadratic in t is reproduced exactly (three-point slopes are exact for it), a
// smooth signal to O(h^3), and the report says what was found.
TEST(DatasetFormats, JitteredTimestampsAreResampledOntoTheMedianGrid) {
  std::string text = kHeader + ",qd_hip,qd_knee\n";
  double t = 0.0;
  for (int i = 0; i < 400; ++i) {
    const double jitter = (i % 7 == 3) ? 0.0016 : (i % 5 == 1 ? -0.0003 : 0.0);  // 2 ms nominal
    t = 0.002 * i + jitter;
    char row[200];
    std::snprintf(row, sizeof row, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", t, 1.0 + 2.0 * t - 3.0 * t * t,
                  std::sin(2 * M_PI * t), 0.5, std::cos(3.0 * t), 2.0 - 6.0 * t, 2 * M_PI * std::cos(2 * M_PI * t));
    text += row;
  }
  const Dataset d = parse(text);
  EXPECT_TRUE(d.sampling.resampled);
  EXPECT_EQ(d.sampling.rows_read, 400);
  EXPECT_NEAR(d.sampling.median_dt_s, 0.002, 1e-15);
  EXPECT_NEAR(d.sampling.max_dt_s, 0.0039, 1e-12);  // -0.3 ms then +1.6 ms (rows 16, 17)
  EXPECT_GT(d.sampling.intervals_off, 50);
  ASSERT_GE(d.size(), 398);
  double err_quad = 0.0, err_sin = 0.0;
  for (Eigen::Index k = 0; k < d.size(); ++k) {
    const double tk = d.t_s[k];
    EXPECT_NEAR(tk, 0.002 * static_cast<double>(k), 1e-15);
    err_quad = std::max(err_quad, std::abs(d.q_rad(k, 0) - (1.0 + 2.0 * tk - 3.0 * tk * tk)));
    err_sin = std::max(err_sin, std::abs(d.q_rad(k, 1) - std::sin(2 * M_PI * tk)));
  }
  EXPECT_LT(err_quad, 1e-13);
  // Cubic Hermite with O(h^2) slopes: error <= C h^3 |y'''|, h <= 3.9 ms, |y'''| = (2 pi)^3: ~1e-5.
  EXPECT_LT(err_sin, 1e-5);
  EXPECT_TRUE(d.qd_radps.has_value());
}

}  // namespace
}  // namespace exoid::ident

#include "exoid/ident/io/dataset.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

namespace exoid::ident {
namespace {

std::string header() { return "t,q_hip,q_knee,tau_hip,tau_knee\n"; }
std::string rows(int n, double dt = 0.001) {
  std::string s;
  for (int i = 0; i < n; ++i) s += std::to_string(i * dt) + ",0.1,0.2,1.5,-2.5\n";
  return s;
}

// Parses `text`; expects a DatasetError whose message contains every fragment.
void expectError(const std::string& text, std::vector<std::string> fragments, long line, long column,
                 const CsvReadOptions& options = {}) {
  std::istringstream in(text);
  try {
    parseDatasetCsv(in, "log.csv", options);
    FAIL() << "no error for:\n" << text.substr(0, 200);
  } catch (const DatasetError& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
    EXPECT_EQ(e.line(), line) << msg;
    EXPECT_EQ(e.column(), column) << msg;
    EXPECT_EQ(msg.rfind("log.csv", 0), 0u) << msg;
  }
}

TEST(Dataset, ParsesRequiredOptionalAndExtraColumnsInAnyOrder) {
  std::string text = "# exoid dataset\n# thigh_length_m: 0.44\n"
                     "q_knee,t,tau_knee,tau_hip,q_hip,qd_hip,qd_knee,qdd_hip,qdd_knee,temperature\n";
  for (int i = 0; i < 30; ++i) {
    text += "0.2," + std::to_string(0.002 * i) + ",-2,1,0.1,3,4,5,6,36.5\n";
  }
  std::istringstream in(text);
  const Dataset d = parseDatasetCsv(in, "mem");
  ASSERT_EQ(d.size(), 30);
  EXPECT_DOUBLE_EQ(d.sampleInterval_s(), 0.002);
  EXPECT_EQ(d.q_rad(5, 0), 0.1);
  EXPECT_EQ(d.q_rad(5, 1), 0.2);
  EXPECT_EQ(d.tau_Nm(5, 0), 1.0);
  EXPECT_EQ(d.tau_Nm(5, 1), -2.0);
  ASSERT_TRUE(d.qd_radps && d.qdd_radps2);
  EXPECT_EQ((*d.qdd_radps2)(0, 1), 6.0);
  ASSERT_EQ(d.extra_names, std::vector<std::string>{"temperature"});
  EXPECT_EQ(d.extraColumn("temperature")[29], 36.5);
  EXPECT_EQ(d.metadata("thigh_length_m").value(), "0.44");
  EXPECT_FALSE(d.metadata("gravity_mps2"));
}

TEST(Dataset, WriteReadRoundTripIsLossless) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  Dataset d;
  const Eigen::Index n = 200;
  d.comments = {" seed: 7", " note: round trip"};
  d.t_s = Eigen::VectorXd::LinSpaced(n, 0.0, 0.199);
  d.q_rad = Eigen::MatrixX2d::NullaryExpr(n, 2, [&] { return u(gen) * 1e-3; });
  d.tau_Nm = Eigen::MatrixX2d::NullaryExpr(n, 2, [&] { return u(gen) / 3.0; });
  d.qd_radps = Eigen::MatrixX2d::NullaryExpr(n, 2, [&] { return u(gen) * 1e-17; });
  d.qdd_radps2 = Eigen::MatrixX2d::NullaryExpr(n, 2, [&] { return u(gen) * 1e4; });
  // Known columns are bounded to physical values; extra columns carry the extreme magnitudes.
  d.extra_names = {"a", "b"};
  d.extra = Eigen::MatrixXd::NullaryExpr(n, 2, [&] { return u(gen); });
  d.extra.col(1) *= 1e300 / 1e3;
  const std::string path = ::testing::TempDir() + "/exoid_roundtrip.csv";
  writeDatasetCsv(d, path);
  CsvReadOptions tight;
  tight.dt_rel_tolerance = 1e-6;
  const Dataset r = readDatasetCsv(path, tight);
  EXPECT_EQ(r.comments, d.comments);
  EXPECT_TRUE(r.t_s == d.t_s);  // bitwise equality: %.17g round-trips every double
  EXPECT_TRUE(r.q_rad == d.q_rad);
  EXPECT_TRUE(r.tau_Nm == d.tau_Nm);
  EXPECT_TRUE(*r.qd_radps == *d.qd_radps);
  EXPECT_TRUE(*r.qdd_radps2 == *d.qdd_radps2);
  EXPECT_EQ(r.extra_names, d.extra_names);
  EXPECT_TRUE(r.extra == d.extra);
  std::remove(path.c_str());
}

// Any robot: columns per joint of the model (here a hip-knee-ankle leg), round trip in the
// model's order whatever the file's; the joints' names carried; gaps named.
TEST(Dataset, ReadsAndWritesTheJointsOfAnyModel) {
  CsvReadOptions o;
  o.joints = {"hip", "knee", "ankle"};
  o.format.torque_sign = {1.0, 1.0, -1.0};
  std::string text = "tau_ankle,t,q_ankle,q_hip,q_knee,tau_hip,tau_knee,qd_hip,qd_knee,qd_ankle,grf\n";
  for (int i = 0; i < 25; ++i) text += "3," + std::to_string(0.001 * i) + ",0.3,0.1,0.2,1,2,4,5,6,700\n";
  std::istringstream in(text);
  const Dataset d = parseDatasetCsv(in, "leg3.csv", o);
  ASSERT_EQ(d.joints, o.joints);
  EXPECT_EQ(d.q_rad.cols(), 3);
  EXPECT_DOUBLE_EQ(d.q_rad(4, 2), 0.3);
  EXPECT_DOUBLE_EQ(d.tau_Nm(4, 2), -3.0);  // its sign flipped by the format
  ASSERT_TRUE(d.qd_radps.has_value());
  EXPECT_DOUBLE_EQ((*d.qd_radps)(0, 2), 6.0);
  EXPECT_FALSE(d.qdd_radps2.has_value());
  EXPECT_EQ(d.extra_names, std::vector<std::string>{"grf"});
  std::ostringstream out;
  writeDatasetCsv(d, out);
  EXPECT_EQ(out.str().substr(0, out.str().find('\n')), "t,q_hip,q_knee,q_ankle,tau_hip,tau_knee,tau_ankle,qd_hip,qd_knee,qd_ankle,grf");
  std::istringstream back(out.str());
  CsvReadOptions plain = o;
  plain.format.torque_sign.clear();
  const Dataset again = parseDatasetCsv(back, "again.csv", plain);
  EXPECT_EQ(again.tau_Nm, d.tau_Nm);
  EXPECT_EQ(again.q_rad, d.q_rad);
  // The APAL leg's reader does not take this record as its own, and says what is missing.
  expectError(text, {"missing required column 'tau_ankle'", "required: t,q_hip,q_knee,q_ankle,tau_hip,tau_knee,tau_ankle"}, 1, 0,
              [&] {
                CsvReadOptions c = o;
                c.format.torque_sign.clear();
                c.format.columns = {{"x", "tau_ankle"}};
                return c;
              }());
  expectError(text, {"derivative columns come for every joint", "qdd_"}, 1, 0, [&] {
    CsvReadOptions c = o;
    c.format.torque_sign.clear();
    c.format.columns = {{"qdd_knee", "grf"}};
    return c;
  }());
  expectError(text, {"2 torque signs for 3 joints"}, 0, 0, [&] {
    CsvReadOptions c = o;
    c.format.torque_sign = {1.0, 1.0};
    return c;
  }());
  EXPECT_THROW(d.requireJoints({"hip", "knee"}, "the 2-link leg"), std::invalid_argument);
  // A window of rows keeps every column (the band's pilot and the base terms' judge read one).
  const Dataset w = d.window(3, 5);
  EXPECT_EQ(w.size(), 5);
  EXPECT_EQ(w.joints, d.joints);
  EXPECT_TRUE(w.t_s == d.t_s.segment(3, 5) && w.tau_Nm == d.tau_Nm.middleRows(3, 5) && w.extra == d.extra.middleRows(3, 5));
  EXPECT_TRUE(*w.qd_radps == d.qd_radps->middleRows(3, 5));
  EXPECT_THROW(d.window(21, 5), std::invalid_argument);
  EXPECT_THROW(d.window(-1, 2), std::invalid_argument);
}

TEST(DatasetErrors, EmptyFile) { expectError("", {"empty file", "header"}, 0, 0); }
TEST(DatasetErrors, OnlyComments) { expectError("# a\n# b\n", {"empty file"}, 0, 0); }
TEST(DatasetErrors, MissingColumn) {
  expectError("t,q_hip,q_knee,tau_hip\n" + rows(30), {"missing required column 'tau_knee'"}, 1, 0);
}
TEST(DatasetErrors, DuplicateColumn) {
  expectError("t,q_hip,q_knee,tau_hip,tau_knee,q_hip\n", {"duplicate column 'q_hip'"}, 1, 6);
}
TEST(DatasetErrors, UnpairedDerivative) {
  expectError("t,q_hip,q_knee,tau_hip,tau_knee,qd_hip\n", {"missing column 'qd_knee'"}, 1, 0);
}
TEST(DatasetErrors, NonNumericCell) {
  expectError(header() + rows(5) + "0.005,0.1,abc,1,2\n" + rows(30), {"column 'q_knee'", "expected a number", "'abc'"}, 7, 3);
}
TEST(DatasetErrors, EmptyCell) {
  expectError(header() + "0,0.1,0.2,,1\n", {"column 'tau_hip'", "expected a number"}, 2, 4);
}
TEST(DatasetErrors, NaNAndInf) {
  expectError(header() + "0,0.1,0.2,nan,1\n", {"column 'tau_hip'", "finite"}, 2, 4);
  expectError(header() + "0,inf,0.2,1,1\n", {"column 'q_hip'", "finite"}, 2, 2);
}
TEST(DatasetErrors, WrongCellCount) {
  expectError(header() + "0,0.1,0.2,1\n", {"expected 5 cells", "got 4"}, 2, 0);
}
TEST(DatasetErrors, TooFewRows) {
  expectError(header() + rows(10), {"at least 20 data rows", "got 10"}, 0, 0);
}
TEST(DatasetErrors, TimeNotIncreasing) {
  expectError(header() + "0,0,0,0,0\n0.001,0,0,0,0\n0.001,0,0,0,0\n" + rows(30), {"strictly increasing"}, 4, 1);
}
TEST(DatasetErrors, NonUniformSamplingWhenStrict) {
  std::string text = header();
  for (int i = 0; i < 30; ++i) text += std::to_string(i == 29 ? 0.0295 : 0.001 * i) + ",0,0,0,0\n";
  CsvReadOptions strict;
  strict.sampling = SamplingMode::kStrict;
  expectError(text, {"not uniform", "median", "strict"}, 31, 1, strict);
}
TEST(DatasetErrors, GapTooLongToResampleNamesBothLines) {
  std::string text = header();
  for (int i = 0; i < 30; ++i) text += std::to_string(0.001 * i + (i >= 20 ? 0.05 : 0.0)) + ",0,0,0,0\n";
  // Rows 20 and 21 of the data are lines 21 and 22; the gap is 51 ms against a 10 ms limit.
  expectError(text, {"gap of 0.051 s", "lines 21 and 22", "0.01 s"}, 22, 1);
}
TEST(DatasetErrors, MissingFileNamesPath) {
  try {
    readDatasetCsv("/nonexistent/exoid.csv");
    FAIL();
  } catch (const DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/exoid.csv"), std::string::npos);
  }
}

// A stream that serves `text` and then fails, as a disk error or memory exhaustion mid-file would:
// the reader must not take the rows it got for the whole log (it did: 999 of 2000 rows, exit 0).
class FailingBuf : public std::streambuf {
 public:
  explicit FailingBuf(std::string text) : text_(std::move(text)) { setg(text_.data(), text_.data(), text_.data() + text_.size()); }

 protected:
  int_type underflow() override { throw std::ios_base::failure("injected read error"); }

 private:
  std::string text_;
};

TEST(DatasetErrors, AReadErrorMidFileIsAnErrorNotTheEnd) {
  FailingBuf buf(header() + rows(999));
  std::istream in(&buf);
  try {
    parseDatasetCsv(in, "log.csv");
    FAIL() << "the first 999 rows were taken for the whole file";
  } catch (const DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find("reading failed"), std::string::npos) << e.what();
  }
}
TEST(DatasetErrors, AFolderGivenAsTheLogSaysItCannotBeRead) {
  try {
    readDatasetCsv("/tmp");
    FAIL();
  } catch (const DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find("/tmp"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Is a directory"), std::string::npos) << e.what();
  }
}

TEST(AngleUnitHint, RadiansPassAndDegreesAreNamedWithTheLikelyUnit) {
  Dataset d;
  d.joints = {"hip", "knee"};
  const Eigen::Index n = 3000;
  d.t_s = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-3 * static_cast<double>(n - 1));
  d.q_rad.resize(n, 2);
  d.tau_Nm = Eigen::MatrixXd::Zero(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    d.q_rad(i, 0) = 1.2 * std::sin(2 * M_PI * 0.8 * d.t_s[i]);  // a fast, wide, real motion: 1.2 rad at 0.8 Hz
    d.q_rad(i, 1) = 1.0 + 0.9 * std::sin(2 * M_PI * 1.5 * d.t_s[i]);
  }
  EXPECT_EQ(angleUnitHint(d), "");
  Dataset deg = d;
  deg.q_rad.col(1) *= 180.0 / M_PI;  // the knee logged in degrees: 103 "rad" of span
  const std::string h = angleUnitHint(deg);
  EXPECT_NE(h.find("q_knee spans"), std::string::npos) << h;
  EXPECT_NE(h.find("--angle-unit deg"), std::string::npos) << h;
  // A small motion in degrees still moves too fast as radians: 3 deg at 8 Hz is 151 "rad/s".
  Dataset small = d;
  for (Eigen::Index i = 0; i < n; ++i) small.q_rad(i, 0) = 3.0 * std::sin(2 * M_PI * 8.0 * d.t_s[i]);
  EXPECT_NE(angleUnitHint(small).find("q_hip"), std::string::npos);
}

}  // namespace
}  // namespace exoid::ident

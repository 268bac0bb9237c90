#include "exoid/sim/table.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace exoid::sim {
namespace {

Table sample() {
  Table t;
  t.names = {"t", "q_hip"};
  t.values.resize(2, 2);
  t.values << 0.0, 0.1, 0.001, -1.0 / 3.0;
  t.metadata = {{"seed", "7"}, {"dt_s", "0.001"}};
  return t;
}

TEST(TableTest, CsvFormat) {
  EXPECT_EQ(tableCsv(sample()),
            "# seed: 7\n# dt_s: 0.001\nt,q_hip\n0,0.10000000000000001\n"
            "0.001,-0.33333333333333331\n");
}

TEST(TableTest, SeventeenDigitsRoundTrip) {
  Table t;
  t.names = {"x"};
  t.values.resize(4, 1);
  t.values << M_PI, 1e-300, -123456.789e10, std::nextafter(1.0, 2.0);
  std::istringstream in(tableCsv(t));
  std::string line;
  std::getline(in, line);
  for (int i = 0; i < 4; ++i) {
    std::getline(in, line);
    EXPECT_EQ(std::strtod(line.c_str(), nullptr), t.values(i, 0));
  }
}

TEST(TableTest, AtomicWriteLeavesOnlyTheFile) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path("table_test_dir");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "out.csv").string();
  writeTableCsv(sample(), path);
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1);
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), tableCsv(sample()));
  fs::remove_all(dir);
}

TEST(TableTest, ErrorsNameThePathAndColumn) {
  try {
    writeTableCsv(sample(), "/no/such/dir/out.csv");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/dir/out.csv"), std::string::npos);
  }
  const Table t = sample();
  EXPECT_EQ(t.column("q_hip"), 1);
  try {
    t.column("tau");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'tau'"), std::string::npos);
  }
  Table bad = sample();
  bad.names.pop_back();
  EXPECT_THROW(tableCsv(bad), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::sim

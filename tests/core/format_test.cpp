// One number format for messages and tables: small and negative numbers keep their value (the
// std::to_string it replaced printed -1e-9 as "-0.000000").
#include "exoid/core/format.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace exoid::core {
namespace {

TEST(Format, NumbersKeepTheirValueAtEveryMagnitude) {
  EXPECT_EQ(formatNumber(-1e-9), "-1e-09");
  EXPECT_EQ(formatNumber(1e-300), "1e-300");
  EXPECT_EQ(formatNumber(0.5), "0.5");
  EXPECT_EQ(formatNumber(2.5e300), "2.5e+300");
  EXPECT_EQ(formatNumber(1.0 / 3.0, 4), "0.3333");
  EXPECT_EQ(formatNumber(std::nan("")), "nan");
  EXPECT_EQ(formatNumber(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(formatFixed(1.23456, 2), "1.23");
  EXPECT_EQ(formatFixed(-1e308, 0).size(), 310u);  // no truncation of the widest value
}

TEST(Format, RoundTripsWithSeventeenDigits) {
  const double v = 0.1 + 0.2;
  EXPECT_EQ(std::stod(formatNumber(v, 17)), v);
}

TEST(Format, IntegersExactlyAndFloatsByFormatNumber) {
  EXPECT_EQ(toText(42), "42");
  EXPECT_EQ(toText(-7L), "-7");
  EXPECT_EQ(toText(18446744073709551615ULL), "18446744073709551615");
  EXPECT_EQ(toText(-1e-9), "-1e-09");
  EXPECT_EQ(toText(2.0f), "2");
}

}  // namespace
}  // namespace exoid::core

// ident (what is identified) and sim (what is true) index X by position: both take their names
// and units from core's one table, and agree with each other and with the sidecar's order.
#include "exoid/core/params.hpp"
#include "exoid/ident/leg/params.hpp"
#include "exoid/sim/truth.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

TEST(ParamNames, IdentAndSimAgreeWithCoreByPosition) {
  using namespace exoid;
  ASSERT_EQ(ident::kNumParams, core::kNumParams);
  ASSERT_EQ(sim::kNumParams, core::kNumParams);
  const std::string expected[] = {"Mxt", "Myt", "Jt", "fc1", "fv1", "Mxs", "Mys", "Js", "fc2", "fv2"};
  for (int i = 0; i < core::kNumParams; ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_EQ(std::string(ident::paramName(i)), expected[i]);
    EXPECT_EQ(std::string(sim::paramNames()[k]), expected[i]);
    EXPECT_EQ(std::string(ident::paramInfo()[k].unit), std::string(sim::paramUnits()[k])) << expected[i];
  }
}

}  // namespace

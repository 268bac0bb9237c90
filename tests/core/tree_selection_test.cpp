#include "exoid/core/tree_selection.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace exoid::core {
namespace {

// A record's metadata says its chain as options() text: read back it is the same selection, names
// with spaces and lock postures to the last bit included; "none" and "" are no selection.
TEST(ChainSelection, ItsOptionsTextReadsBackAsTheSameSelection) {
  ChainSelection s;
  s.base = "left hip";
  s.tip = "l_foot";
  s.addLock("l_ankle_pitch=0.1");
  s.addLock("toe \"big\"=-0.30000000000000004");
  EXPECT_EQ(s.options(), "--base \"left hip\" --tip l_foot --lock l_ankle_pitch=0.1 --lock \"toe \\\"big\\\"=-0.30000000000000004\"");
  const ChainSelection back = parseChainSelection(s.options());
  EXPECT_EQ(back.base, s.base);
  EXPECT_EQ(back.tip, s.tip);
  EXPECT_EQ(back.locks, s.locks);
  EXPECT_TRUE(parseChainSelection("none").empty());
  EXPECT_TRUE(parseChainSelection("").empty());
  EXPECT_EQ(ChainSelection{}.label(), "none");
  for (const char* bad : {"--base", "--root pelvis", "--lock knee"}) EXPECT_THROW(parseChainSelection(bad), std::invalid_argument) << bad;
}

}  // namespace
}  // namespace exoid::core

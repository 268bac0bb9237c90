// A chain other than the APAL leg drawn offscreen (leg3): a still per pose, different poses
// different images, the same pose the same bytes; errors name what is wrong.
#include "exoid/render/chain_clip.hpp"
#include "exoid/sim/model.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace exoid::render {
namespace {

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(ChainClip, StillsFollowThePoseAndRepeatByteForByte) {
  const std::string dir = ::testing::TempDir();
  const std::string model = sim::modelPathFor("leg3");
  const std::vector<std::string> joints = {"hip", "knee", "ankle"};
  Eigen::VectorXd t(3);
  t << 0.0, 1.0, 2.0;
  Eigen::MatrixXd q(3, 3);
  q << 0.0, 0.2, 0.0,  //
      -1.2, 1.5, 0.3,  //
      0.0, 0.2, 0.0;
  ChainClipOptions o;
  o.render.width = 160;
  o.render.height = 120;
  renderChain(model, joints, t, q, dir + "/a.png", o, 0.0);
  renderChain(model, joints, t, q, dir + "/b.png", o, 1.0);
  renderChain(model, joints, t, q, dir + "/c.png", o, 2.0);
  const std::string a = bytesOf(dir + "/a.png"), b = bytesOf(dir + "/b.png"), c = bytesOf(dir + "/c.png");
  EXPECT_GT(a.size(), 1000u);
  EXPECT_NE(a, b);  // the leg moved
  EXPECT_EQ(a, c);  // same pose, same bytes
  EXPECT_THROW(renderChain(model, {"hip", "knee", "toe"}, t, q, dir + "/x.png", o, 0.0), std::invalid_argument);
  EXPECT_THROW(renderChain(model, joints, t, q, dir + "/x.png", o, 5.0), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.png"));
}

}  // namespace
}  // namespace exoid::render

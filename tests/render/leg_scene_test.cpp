// The posed scene: loop closed, hip/knee where the angles say, bodies colored apart.
#include "exoid/render/leg_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace exoid::render {
namespace {

TEST(LegScene, PoseClosesTheLoopAndPlacesTheKnee) {
  LegScene scene(sim::defaultModelPath(), /*with_mount=*/false);
  const double q1 = -0.6, q2 = 1.2;
  scene.setPose({q1, q2, 0, 0, 0});
  const mjModel* m = scene.model();
  const mjData* d = scene.data();
  // The analytic closure leaves the loop closed to round-off (docs/mujoco.md note 3: 1e-9 m at assembly).
  EXPECT_LT(sim::loopError(m, d, scene.indices()), 1e-9);
  // Knee = hip + R_y(q1) (0, 0, -0.45): x = -0.45 sin(q1), z = -0.45 cos(q1) relative to the hip.
  const double* hip = d->xpos + 3 * scene.indices().body_thigh;
  const double* knee = d->xpos + 3 * scene.indices().body_shank;
  EXPECT_NEAR(knee[0] - hip[0], -0.45 * std::sin(q1), 1e-12);
  EXPECT_NEAR(knee[2] - hip[2], -0.45 * std::cos(q1), 1e-12);
}

TEST(LegScene, MountMovesThePedestal) {
  LegScene scene(sim::defaultModelPath(), /*with_mount=*/true);
  ASSERT_TRUE(scene.hasMount());
  scene.setPose({0, 0.5, 0.01, -0.02, 0});
  const double* p = scene.data()->xpos + 3 * scene.indices().body_pedestal;
  EXPECT_NEAR(p[0], 0.01, 1e-12);
  EXPECT_NEAR(p[2], -0.02, 1e-12);
}

TEST(LegScene, BodiesHaveDistinctColors) {
  LegScene scene(sim::defaultModelPath(), false);
  const mjModel* m = scene.model();
  const sim::LegIndices& x = scene.indices();
  const int bodies[] = {x.body_pedestal, x.body_trunk, x.body_thigh, x.body_shank, x.body_cylinder, x.body_rod};
  // One representative (non-housing) geom per body; colors at least 0.25 apart (RGB, max norm).
  std::vector<const float*> colors;
  for (int b : bodies) {
    for (int g = 0; g < m->ngeom; ++g) {
      const char* name = mj_id2name(m, mjOBJ_GEOM, g);
      if (m->geom_bodyid[g] == b && !(name && std::string(name).find("housing") != std::string::npos)) {
        colors.push_back(m->geom_rgba + 4 * g);
        break;
      }
    }
  }
  ASSERT_EQ(colors.size(), 6u);
  for (std::size_t i = 0; i < colors.size(); ++i) {
    for (std::size_t j = i + 1; j < colors.size(); ++j) {
      float dist = 0;
      for (int c = 0; c < 3; ++c) dist = std::max(dist, std::abs(colors[i][c] - colors[j][c]));
      EXPECT_GT(dist, 0.25f) << "bodies " << i << " and " << j;
    }
  }
}

}  // namespace
}  // namespace exoid::render

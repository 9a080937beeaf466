// compensateMotion: points moved from their own time to the scan's reference time.
#include <gtest/gtest.h>

#include "radar_ndt/odometry/motion_compensation.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

TEST(CompensateMotion, MovesPointsToTheReferenceTime) {
  // The vehicle drives at 10 m/s turning at 0.5 rad/s; a wall point measured at τ = 0.2 s, seen
  // from the pose then, is moved into the frame at τ = 0.
  const Eigen::Vector3d v(10, 0, 0.5);
  const Pose2 at_tau = integrateVelocity(v, 0.2);
  const Eigen::Vector2d world(20, 5);  // in the frame at τ = 0
  const Eigen::Vector2d seen = toIsometry2<double>(at_tau).inverse() * world;
  pcl::PointCloud<PointRadar> cloud, out;
  PointRadar p(static_cast<float>(seen.x()), static_cast<float>(seen.y()), 0.f);
  p.time_offset = 0.2f;
  p.cov_xx = 0.04f;
  p.cov_yy = 0.01f;
  cloud.push_back(p);
  compensateMotion(cloud, v, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].x, world.x(), 2e-3);
  EXPECT_NEAR(out[0].y, world.y(), 2e-3);
  EXPECT_EQ(out[0].time_offset, 0.f);
  EXPECT_NEAR(out[0].cov_xx + out[0].cov_yy, 0.05f, 1e-6);  // a rotation keeps the trace
}

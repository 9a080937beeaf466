// The automotive front-end (frontend/automotive_front_end.h): each sweep moved to the reference
// time, each radar's covariances along its own beam.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "radar_ndt/frontend/automotive_front_end.h"
#include "radar_ndt/frontend/ego_velocity.h"
#include "radar_ndt/frontend/point_covariance.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

TEST(AutomotiveFrontEnd, EachSweepIsMovedToTheReferenceTime) {
  // A car at 10 m/s and static points P (vehicle frame at the reference time): the reference
  // sweep sees them at P, a sweep 50 ms earlier, taken 0.5 m further back, at P + (0.5, 0). After
  // the front-end both sit at P: the earlier sweep is moved forward in time by exp(v dt).
  const Eigen::Vector3d v(10.0, 0.0, 0.0);
  Eigen::Isometry3d front = Eigen::Isometry3d::Identity();  // a front radar, as on the nuScenes car
  front.translation() = Eigen::Vector3d(3.4, 0.0, 0.5);
  const SensorMounting mounting = toMounting(front);
  std::vector<Eigen::Vector2d> world;
  for (int i = 0; i < 30; ++i) world.emplace_back(15.0 + i, -8.0 + 4.0 * (i % 5));
  RadarCycle cycle;
  cycle.timestamp_us = 1000000;
  for (const std::int64_t t : {std::int64_t{1000000}, std::int64_t{950000}}) {
    RadarSweepData sweep;
    sweep.timestamp_us = t;
    sweep.sensor_id = 0;
    sweep.sensor_to_vehicle = front;
    const double back = 1e-6 * static_cast<double>(cycle.timestamp_us - t) * v.x();
    for (const auto& w : world) {
      const double x = w.x() + back, y = w.y();                               // vehicle frame at the sweep's time
      PointRadar p(static_cast<float>(x - 3.4), static_cast<float>(y), 0.f);  // sensor frame
      p.doppler = static_cast<float>(predictedDoppler(mounting, x, y, v));
      sweep.points.push_back(p);
    }
    cycle.sweeps.push_back(sweep);
  }
  const ProcessedCycle out = AutomotiveFrontEnd().process(cycle);
  ASSERT_TRUE(out.ego.valid);
  EXPECT_NEAR(out.ego.velocity.x(), 10.0, 1e-3);
  ASSERT_EQ(out.cloud->size(), 2 * world.size()) << "every point is static";
  for (std::size_t i = 0; i < out.cloud->size(); ++i) {
    const Eigen::Vector2d& w = world[i % world.size()];
    EXPECT_NEAR((*out.cloud)[i].x, w.x(), 2e-3) << "point " << i;
    EXPECT_NEAR((*out.cloud)[i].y, w.y(), 2e-3) << "point " << i;
  }
}

// Every radar's detections carry covariances that lie along its own beam in the vehicle frame:
// the polar model's (narrow along the range, wide across it) turned by that radar's mounting yaw,
// for each of the nuScenes car's five radars (front, sides, and the rear two looking backwards).
TEST(AutomotiveFrontEnd, EachRadarsCovariancesLieAlongItsOwnBeam) {
  const double kDeg = kPi / 180.0;
  const double yaws_deg[5] = {0.2, 88.36, -90.98, 174.41, -176.11};
  RadarCycle cycle;
  cycle.timestamp_us = 1000000;
  const Eigen::Vector2d in_sensor(60.0 * std::cos(30.0 * kDeg), 60.0 * std::sin(30.0 * kDeg));
  for (std::uint16_t id = 0; id < 5; ++id) {
    RadarSweepData sweep;
    sweep.timestamp_us = cycle.timestamp_us;  // at the reference time: nothing moves
    sweep.sensor_id = id;
    sweep.sensor_to_vehicle = Eigen::Isometry3d::Identity();
    sweep.sensor_to_vehicle.linear() = Eigen::AngleAxisd(yaws_deg[id] * kDeg, Eigen::Vector3d::UnitZ()).matrix();
    sweep.sensor_to_vehicle.translation() = Eigen::Vector3d(1.0 * id, -0.5 * id, 0.5);
    PointRadar p(static_cast<float>(in_sensor.x()), static_cast<float>(in_sensor.y()), 0.f, 1.f);
    sweep.points.push_back(p);
    cycle.sweeps.push_back(sweep);
  }
  AutomotiveFrontEndOptions o;
  o.remove_moving = false;
  const ProcessedCycle out = AutomotiveFrontEnd(o).process(cycle);
  ASSERT_EQ(out.cloud->size(), 5u);
  const Eigen::Matrix2d in_sensor_cov = polarCovariance(in_sensor.x(), in_sensor.y(), o.polar);
  for (std::size_t i = 0; i < 5; ++i) {
    const PointRadar& q = (*out.cloud)[i];
    ASSERT_LT(q.sensor_id, 5u);
    const double beam = (yaws_deg[q.sensor_id] + 30.0) * kDeg;  // the point's bearing from its radar
    const Eigen::Vector2d along(std::cos(beam), std::sin(beam)), across(-along.y(), along.x());
    Eigen::Matrix2d C;
    C << q.cov_xx, q.cov_xy, q.cov_xy, q.cov_yy;
    EXPECT_NEAR(along.dot(C * along), 0.1 * 0.1, 1e-4) << "radar " << q.sensor_id << ": σ along its beam";
    EXPECT_NEAR(across.dot(C * across), in_sensor_cov(1, 1) + in_sensor_cov(0, 0) - 0.01, 1e-3)
        << "radar " << q.sensor_id << ": σ across its beam";
    EXPECT_NEAR(along.dot(C * across), 0.0, 1e-4) << "radar " << q.sensor_id;
  }
}

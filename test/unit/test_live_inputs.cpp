// The ROS node's live inputs, planned as the offline run plans a whole recording: radar cycles as
// sweeps arrive (LiveCycles) and the car's gyro and speed as their messages arrive
// (LiveVehicleSignals).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "radar_ndt/io/live_cycles.h"
#include "radar_ndt/io/live_vehicle_signals.h"

using namespace radar_ndt;

namespace {
RadarSweepData sweepAt(std::int64_t t_us, std::uint16_t channel) {
  RadarSweepData s;
  s.timestamp_us = t_us;
  s.sensor_id = channel;
  return s;
}
}  // namespace

// The node's cycles as they arrive: the offline planner's rule, a cycle handed out once the other
// radars have moved past it (so a radar's sweep that comes after the reference's is not missed), a
// silent radar not waited for, late and repeated sweeps refused, a reset for a bag played again.
TEST(LiveCycles, PlansAsTheOfflinePlannerAsSweepsArrive) {
  LiveCycles live(0, 100000);
  EXPECT_EQ(live.add(sweepAt(1000000, 0)), LiveCycles::Added::Taken);
  EXPECT_EQ(live.add(sweepAt(950000, 1)), LiveCycles::Added::Taken);
  EXPECT_FALSE(live.next()) << "radar 1 may still send a sweep up to t_ref";
  EXPECT_EQ(live.add(sweepAt(990000, 1)), LiveCycles::Added::Taken);  // arrives after the reference's
  EXPECT_FALSE(live.next());
  EXPECT_EQ(live.add(sweepAt(1030000, 1)), LiveCycles::Added::Taken);
  auto c = live.next();
  ASSERT_TRUE(c);
  EXPECT_EQ(c->timestamp_us, 1000000);
  ASSERT_EQ(c->sweeps.size(), 2u);
  EXPECT_EQ(c->sweeps[1].timestamp_us, 990000) << "the latest within the period before";
  EXPECT_EQ(live.add(sweepAt(995000, 1)), LiveCycles::Added::Late);
  EXPECT_EQ(live.add(sweepAt(1030000, 1)), LiveCycles::Added::Repeated);
  // Radar 1 falls silent: after a second of the stream the cycles go on without it.
  for (int k = 1; k <= 13; ++k) live.add(sweepAt(1000000 + 100000 * k, 0));
  std::size_t out = 0;
  while (auto next = live.next()) ++out;
  EXPECT_GE(out, 1u);
  EXPECT_EQ(live.flush().size() + out, 13u);
  live.reset();
  EXPECT_EQ(live.add(sweepAt(500000, 0)), LiveCycles::Added::Taken) << "after a reset, earlier times are taken";
}

// The start of a stream (or of a bag played again): the expected radars are waited for before
// they have spoken, so the first cycle holds the sweep a radar whose message arrives last sent
// before the reference's; an expected radar that never speaks holds the cycles for a second.
TEST(LiveCycles, TheFirstCyclesWaitForEveryExpectedRadar) {
  LiveCycles live(0, 100000, {0, 1, 2});
  live.add(sweepAt(990000, 1));
  live.add(sweepAt(1000000, 0));
  live.add(sweepAt(1010000, 1));
  EXPECT_FALSE(live.next()) << "radar 2 has not spoken: its sweep before t_ref may be on the way";
  live.add(sweepAt(980000, 2));
  EXPECT_FALSE(live.next()) << "radar 2 may still send a sweep up to t_ref";
  live.add(sweepAt(1020000, 2));
  auto c = live.next();
  ASSERT_TRUE(c);
  EXPECT_EQ(c->sweeps.size(), 3u) << "the late speaker's sweep is in the first cycle";
  // An expected radar that never speaks: the cycles go on after a second of the stream.
  LiveCycles silent(0, 100000, {0, 1, 2});
  for (int k = 0; k <= 9; ++k) {
    silent.add(sweepAt(1000000 + 100000 * k, 0));
    silent.add(sweepAt(1010000 + 100000 * k, 1));
  }
  EXPECT_FALSE(silent.next()) << "the stream has run 0.9 s: radar 2 is still waited for";
  silent.add(sweepAt(2000000, 0));
  EXPECT_TRUE(silent.next()) << "after over a second it is not";
}

// The node's gyro as messages arrive: the series the offline reader builds from the whole bag
// (sorted, a repeated stamp's first value, NaN left out), a cycle released only once a sample at
// or after its time has arrived (or the gyro is a second of the stream silent), integrals equal to
// the whole series', late samples refused once their interval has been integrated.
TEST(LiveVehicleSignals, GrowAsTheOfflineSeriesAndReleaseACycleOnceReached) {
  using Signal = LiveVehicleSignals::Signal;
  const Signal yaw = Signal::YawRate;
  LiveVehicleSignals live("/imu");
  TimeSeries offline;
  const std::vector<std::pair<std::int64_t, double>> arrivals{{0, 0.10},    {10000, 0.12}, {30000, 0.20}, {20000, 0.15},
                                                              {30000, 9.0}, {40000, 0.25}, {50000, 0.30}};
  for (const auto& [t, v] : arrivals) live.add(yaw, t, v);
  for (const auto& [t, v] : std::vector<std::pair<std::int64_t, double>>{
           {0, 0.10}, {10000, 0.12}, {20000, 0.15}, {30000, 0.20}, {40000, 0.25}, {50000, 0.30}}) {
    offline.stamps_us.push_back(t);
    offline.values.push_back(v);
  }
  const TimeSeries& s = live.signals()->yaw_rate;
  EXPECT_EQ(s.stamps_us, offline.stamps_us) << "out of order to its place, the repeated stamp's first value";
  EXPECT_EQ(s.values, offline.values);
  EXPECT_EQ(live.add(yaw, 60000, std::nan("")), LiveVehicleSignals::Added::NotFinite);
  EXPECT_EQ(live.signals()->dropped, 1u);
  // A cycle ending at 45 ms is reached (50 ms is there); one at 55 ms not, until the gyro is silent
  // for a second of the stream.
  EXPECT_TRUE(live.reaches(45000, 60000));
  EXPECT_TRUE(live.reaches(50000, 60000));
  EXPECT_FALSE(live.reaches(55000, 60000));
  EXPECT_FALSE(live.reaches(55000, 1055000));
  EXPECT_TRUE(live.reaches(55000, 1055001));
  // Integrating to 25 ms forgets what no later integral needs, nothing else.
  EXPECT_DOUBLE_EQ(s.integral(5000, 25000), offline.integral(5000, 25000));
  live.used(25000);
  EXPECT_EQ(s.stamps_us.front(), 20000) << "the last sample at or before 25 ms is kept for the interpolation";
  EXPECT_DOUBLE_EQ(s.integral(25000, 47000), offline.integral(25000, 47000));
  EXPECT_EQ(live.add(yaw, 24000, 1.0), LiveVehicleSignals::Added::Late);
  EXPECT_EQ(live.add(yaw, 26000, 0.21), LiveVehicleSignals::Added::Taken) << "after the integrated time: taken";
  live.reset();
  EXPECT_TRUE(live.signals()->yaw_rate.empty());
  EXPECT_EQ(live.add(yaw, 0, 0.1), LiveVehicleSignals::Added::Taken) << "after a reset, earlier times are taken";
  EXPECT_FALSE(live.reaches(1000, 1000));
}

// With the speed in use too, a cycle waits for both signals; each is forgotten and refused late as
// the yaw rate is, and a silent one stops being waited for after a second of the stream.
TEST(LiveVehicleSignals, ACycleWaitsForEverySignalInUse) {
  using Signal = LiveVehicleSignals::Signal;
  LiveVehicleSignals live("/imu", {Signal::YawRate, Signal::Speed});
  for (std::int64_t t = 0; t <= 50000; t += 10000) live.add(Signal::YawRate, t, 0.1);
  live.add(Signal::Speed, 0, 5.0);
  live.add(Signal::Speed, 20000, 6.0);
  EXPECT_FALSE(live.reaches(30000, 50000)) << "the speed has not reached 30 ms";
  live.add(Signal::Speed, 40000, 7.0);
  EXPECT_TRUE(live.reaches(30000, 50000));
  EXPECT_FALSE(live.reaches(45000, 50000));
  EXPECT_TRUE(live.reaches(45000, 1045001)) << "a speed silent for a second is not waited for";
  EXPECT_DOUBLE_EQ(live.signals()->speed.integral(0, 40000), 0.02 * 5.5 + 0.02 * 6.5);
  live.used(30000);
  EXPECT_EQ(live.signals()->speed.stamps_us.front(), 20000);
  EXPECT_EQ(live.signals()->yaw_rate.stamps_us.front(), 30000);
  EXPECT_EQ(live.add(Signal::Speed, 25000, 1.0), LiveVehicleSignals::Added::Late);
  EXPECT_EQ(live.add(Signal::Speed, 50000, std::nan("")), LiveVehicleSignals::Added::NotFinite);
}

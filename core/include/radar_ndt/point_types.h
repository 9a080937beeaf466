#pragma once
// radar_ndt::PointRadar: one radar return, scanning or automotive, as a PCL point type.
// Part of RadarNDT::core (header-only): every layer (io, registration, front-ends) shares it.

#include <cstdint>

#include <pcl/point_types.h>
#include <pcl/register_point_struct.h>

namespace radar_ndt {

struct EIGEN_ALIGN16 PointRadar {
  PCL_ADD_POINT4D;  // x, y, z (m) and padding; frame given by the producer (sensor or vehicle)
  /// Weight source of the paper's eq. (1)-(2): a scanning radar's returned power scaled to 0..1;
  /// 1 for automotive detections, which the paper weights equally.
  float power;
  /// Radar cross section (dBsm), automotive radars; 0 when unknown.
  float rcs;
  /// 2x2 position covariance of the point (m^2), in the same frame as x, y.
  float cov_xx;
  float cov_xy;
  float cov_yy;
  /// Radial velocity relative to the sensor (m/s), positive when the target recedes.
  float doppler;
  /// Time of the measurement relative to the scan's reference time (s), for motion compensation.
  float time_offset;
  /// Which sensor produced the point (index into the dataset's radar channels).
  std::uint16_t sensor_id;

  inline PointRadar()
      : power(1.f), rcs(0.f), cov_xx(0.f), cov_xy(0.f), cov_yy(0.f), doppler(0.f), time_offset(0.f), sensor_id(0) {
    x = y = z = 0.f;
    data[3] = 1.f;
  }
  inline PointRadar(float px, float py, float pz, float p = 1.f) : PointRadar() {
    x = px;
    y = py;
    z = pz;
    power = p;
  }
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

/// One detection of a 4D radar (x, y, z, Doppler, power): PointRadar's fields with a full 3x3
/// position covariance, since a 4D radar's elevation is far coarser than its range. Its own type,
/// so PointRadar (and every planar file written from it) keeps its layout.
struct EIGEN_ALIGN16 PointRadar4D {
  PCL_ADD_POINT4D;  // x, y, z (m) and padding; frame given by the producer (sensor or vehicle)
  /// Weight source of eq. (1)-(2): the detection's power (or SNR) as the description maps it.
  float power;
  /// Radar cross section (dBsm); 0 when unknown.
  float rcs;
  /// 3x3 position covariance (m^2), upper triangle, in the same frame as x, y, z.
  float cov_xx;
  float cov_xy;
  float cov_xz;
  float cov_yy;
  float cov_yz;
  float cov_zz;
  /// Radial velocity relative to the sensor (m/s), positive when the target recedes.
  float doppler;
  /// Time of the measurement relative to the scan's reference time (s).
  float time_offset;
  /// Which sensor produced the point.
  std::uint16_t sensor_id;

  inline PointRadar4D()
      : power(1.f),
        rcs(0.f),
        cov_xx(0.f),
        cov_xy(0.f),
        cov_xz(0.f),
        cov_yy(0.f),
        cov_yz(0.f),
        cov_zz(0.f),
        doppler(0.f),
        time_offset(0.f),
        sensor_id(0) {
    x = y = z = 0.f;
    data[3] = 1.f;
  }
  inline PointRadar4D(float px, float py, float pz, float p = 1.f) : PointRadar4D() {
    x = px;
    y = py;
    z = pz;
    power = p;
  }
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

}  // namespace radar_ndt

// clang-format off
POINT_CLOUD_REGISTER_POINT_STRUCT(radar_ndt::PointRadar,
  (float, x, x)
  (float, y, y)
  (float, z, z)
  (float, power, power)
  (float, rcs, rcs)
  (float, cov_xx, cov_xx)
  (float, cov_xy, cov_xy)
  (float, cov_yy, cov_yy)
  (float, doppler, doppler)
  (float, time_offset, time_offset)
  (std::uint16_t, sensor_id, sensor_id))

POINT_CLOUD_REGISTER_POINT_STRUCT(radar_ndt::PointRadar4D,
  (float, x, x)
  (float, y, y)
  (float, z, z)
  (float, power, power)
  (float, rcs, rcs)
  (float, cov_xx, cov_xx)
  (float, cov_xy, cov_xy)
  (float, cov_xz, cov_xz)
  (float, cov_yy, cov_yy)
  (float, cov_yz, cov_yz)
  (float, cov_zz, cov_zz)
  (float, doppler, doppler)
  (float, time_offset, time_offset)
  (std::uint16_t, sensor_id, sensor_id))
// clang-format on

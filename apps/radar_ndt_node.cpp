// radar_ndt_node: the radar odometry as a ROS 1 node (docs/ros.md). The sensor description
// (~sensors) says which pipeline runs: point-cloud radars, the automotive one
// (node/automotive_node.cpp); one scanning radar's polar images, the scanning one
// (node/scanning_node.cpp); a 4D radar with a 6-DoF ~matcher/method (pw-ndt-3d, pcl-ndt-3d,
// pcl-gicp), the 6-DoF one (node/inertial_node.cpp). Each publishes ~odometry (nav_msgs/Odometry
// with the match's covariance; 6-DoF: z, the full rotation, the 6x6 covariance), the TF odom ->
// base_link (REP 105), ~local_map (sensor_msgs/PointCloud2, what the next scan is matched against,
// in base_link), ~map (planar: the points --map-out writes, in odom, latched, every tenth cycle)
// and /diagnostics. Its parameters are the run options' field table: ~odometry/submap_size,
// ~matcher/method, ... (one source with the command line and Python).
#include <stdexcept>

#include <ros/ros.h>

#include "node/node_common.h"
#include "radar_ndt/pipeline/inertial_run.h"

using namespace radar_ndt;

int main(int argc, char** argv) {
  ros::init(argc, argv, "radar_ndt");
  ros::NodeHandle nh, pn("~");
  try {
    std::string sensors;
    if (!pn.getParam("sensors", sensors)) throw std::invalid_argument("~sensors: the sensor description is required");
    const SensorDescription d = readSensorDescription(sensors);
    const bool scanning = !d.radars.empty() && d.radars[0].kind == RadarKind::Scanning;
    std::string method;
    const bool inertial = !scanning && pn.getParam("matcher/method", method) && isInertialMethod(method);
    const std::unique_ptr<node::RadarNode> n = scanning   ? node::scanningNode(nh, pn, d)
                                               : inertial ? node::inertialNode(nh, pn, d)
                                                          : node::automotiveNode(nh, pn, d);
    ros::spin();
    n->report();
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("radar_ndt_node: " << e.what());
    return 1;
  }
  return 0;
}

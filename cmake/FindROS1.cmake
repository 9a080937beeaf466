# FindROS1: Debian's ROS 1 (Noetic-era packages: ros-core-dev, librosbag-dev, libtf2-dev, libtf2-msgs-dev, the
# message packages) as imported targets, without catkin: Debian's catkin configurations of rosbag
# pull in pluginlib's ament (ROS 2) CMake, which runs a Python module that only the system Python
# has. What RadarNDT uses is plain headers and shared libraries, found here directly.
#
#   ROS1::rosbag   rosbag_storage (read and write bags) and its serialisation and time libraries
#   ROS1::tf2      tf2 (BufferCore: the radars' mountings through chains of frames, libtf2-dev)
#   ROS1::roscpp   roscpp (a node: publishers, subscribers, the master) with the above, and
#                  topic_tools (a subscription of either of two message types: ShapeShifter)
#   ROS1_FOUND     both found, and the message headers (sensor_msgs, nav_msgs, geometry_msgs,
#                  tf2_msgs, std_msgs)
include(FindPackageHandleStandardArgs)
find_path(ROS1_ROSBAG_INCLUDE_DIR rosbag/bag.h)
find_path(ROS1_ROSCPP_INCLUDE_DIR ros/ros.h)
find_path(ROS1_MSGS_INCLUDE_DIR sensor_msgs/PointCloud2.h)
find_path(ROS1_NAV_MSGS_INCLUDE_DIR nav_msgs/Odometry.h)
find_path(ROS1_TF2_MSGS_INCLUDE_DIR tf2_msgs/TFMessage.h)
find_path(ROS1_TF2_INCLUDE_DIR tf2/buffer_core.h)
# rosbag/bag.h includes pluginlib's headers, which Debian ships in ROS 2's nested layout.
find_path(ROS1_PLUGINLIB_INCLUDE_DIR pluginlib/class_loader.hpp PATH_SUFFIXES pluginlib)
find_path(ROS1_CLASS_LOADER_INCLUDE_DIR class_loader/class_loader.hpp PATH_SUFFIXES class_loader)
find_path(ROS1_AMENT_INDEX_INCLUDE_DIR ament_index_cpp/get_package_prefix.hpp PATH_SUFFIXES ament_index_cpp)
find_path(ROS1_RCUTILS_INCLUDE_DIR rcutils/logging_macros.h PATH_SUFFIXES rcutils)
find_path(ROS1_RCPPUTILS_INCLUDE_DIR rcpputils/shared_library.hpp PATH_SUFFIXES rcpputils)
foreach(lib rosbag_storage roscpp_serialization rostime cpp_common console_bridge roscpp rosconsole
            xmlrpcpp roslz4 topic_tools tf2)
  find_library(ROS1_${lib}_LIBRARY ${lib})
endforeach()
find_package_handle_standard_args(ROS1 REQUIRED_VARS
  ROS1_ROSBAG_INCLUDE_DIR ROS1_ROSCPP_INCLUDE_DIR ROS1_MSGS_INCLUDE_DIR ROS1_NAV_MSGS_INCLUDE_DIR
  ROS1_TF2_MSGS_INCLUDE_DIR ROS1_TF2_INCLUDE_DIR ROS1_PLUGINLIB_INCLUDE_DIR ROS1_CLASS_LOADER_INCLUDE_DIR
  ROS1_AMENT_INDEX_INCLUDE_DIR ROS1_RCUTILS_INCLUDE_DIR ROS1_RCPPUTILS_INCLUDE_DIR
  ROS1_rosbag_storage_LIBRARY ROS1_roscpp_serialization_LIBRARY ROS1_rostime_LIBRARY
  ROS1_cpp_common_LIBRARY ROS1_console_bridge_LIBRARY ROS1_roscpp_LIBRARY ROS1_rosconsole_LIBRARY
  ROS1_xmlrpcpp_LIBRARY ROS1_topic_tools_LIBRARY ROS1_tf2_LIBRARY)
if(ROS1_FOUND AND NOT TARGET ROS1::rosbag)
  find_package(Boost REQUIRED COMPONENTS filesystem)
  add_library(ROS1::rosbag INTERFACE IMPORTED)
  set_target_properties(ROS1::rosbag PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${ROS1_ROSBAG_INCLUDE_DIR};${ROS1_PLUGINLIB_INCLUDE_DIR};${ROS1_CLASS_LOADER_INCLUDE_DIR};${ROS1_AMENT_INDEX_INCLUDE_DIR};${ROS1_RCUTILS_INCLUDE_DIR};${ROS1_RCPPUTILS_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${ROS1_rosbag_storage_LIBRARY};${ROS1_roscpp_serialization_LIBRARY};${ROS1_rostime_LIBRARY};${ROS1_cpp_common_LIBRARY};${ROS1_console_bridge_LIBRARY};Boost::filesystem")
  add_library(ROS1::tf2 INTERFACE IMPORTED)
  set_target_properties(ROS1::tf2 PROPERTIES
    INTERFACE_LINK_LIBRARIES "ROS1::rosbag;${ROS1_tf2_LIBRARY}")
  # The message headers use the system include path, where they already are.
  add_library(ROS1::roscpp INTERFACE IMPORTED)
  set_target_properties(ROS1::roscpp PROPERTIES
    INTERFACE_LINK_LIBRARIES "ROS1::rosbag;${ROS1_roscpp_LIBRARY};${ROS1_rosconsole_LIBRARY};${ROS1_xmlrpcpp_LIBRARY};${ROS1_topic_tools_LIBRARY}")
endif()
mark_as_advanced(ROS1_ROSBAG_INCLUDE_DIR ROS1_ROSCPP_INCLUDE_DIR ROS1_MSGS_INCLUDE_DIR)

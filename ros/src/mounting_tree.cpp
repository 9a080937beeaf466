#include "radar_ndt/ros/mounting_tree.h"

#include <cmath>

#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>

namespace radar_ndt {
namespace ros1 {

MountingTree::MountingTree() : buffer_(std::make_unique<tf2::BufferCore>()) {}
MountingTree::~MountingTree() = default;
MountingTree::MountingTree(MountingTree&&) noexcept = default;
MountingTree& MountingTree::operator=(MountingTree&&) noexcept = default;

void MountingTree::add(const tf2_msgs::TFMessage& message, const std::string& topic,
                       std::vector<std::string>* problems) {
  for (const geometry_msgs::TransformStamped& t : message.transforms) {
    if (t.child_frame_id.empty() || t.header.frame_id.empty() || children_.count(t.child_frame_id)) continue;
    const auto& q = t.transform.rotation;
    const auto& p = t.transform.translation;
    const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    if (!(std::abs(norm - 1.0) < 1e-2) || !std::isfinite(p.x + p.y + p.z)) {
      if (problems)
        problems->push_back(topic + ": " + t.header.frame_id + " -> " + t.child_frame_id +
                            ": rotation quaternion of norm " + std::to_string(norm) +
                            " or a position that is not finite: left out");
      continue;
    }
    geometry_msgs::TransformStamped fixed = t;
    fixed.header.stamp = ros::Time(0);  // a mounting holds for all times
    // A static edge: tf2 answers a lookup at any time with it.
    if (buffer_->setTransform(fixed, "radar_ndt", true)) children_.insert(t.child_frame_id);
  }
}

std::optional<Eigen::Isometry3d> MountingTree::lookup(const std::string& base, const std::string& frame,
                                                      std::string* why) const {
  if (base == frame) return Eigen::Isometry3d::Identity();
  try {
    const geometry_msgs::TransformStamped t = buffer_->lookupTransform(base, frame, ros::Time(0));
    // Normalised as the readers normalise a quaternion, so that one edge gives its message's
    // rotation exactly as before.
    Eigen::Quaterniond q(t.transform.rotation.w, t.transform.rotation.x, t.transform.rotation.y,
                         t.transform.rotation.z);
    q.normalize();
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() << t.transform.translation.x, t.transform.translation.y, t.transform.translation.z;
    return T;
  } catch (const tf2::TransformException& e) {
    if (why) *why = "no transform " + base + " -> " + frame + " in /tf_static or /tf (" + e.what() + ")";
    return std::nullopt;
  }
}

}  // namespace ros1
}  // namespace radar_ndt

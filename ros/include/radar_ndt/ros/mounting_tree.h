#pragma once
// The radars' mountings from /tf_static and /tf, resolved as tf2 resolves them (tf2::BufferCore,
// Debian's libtf2-dev): a radar reached through a chain of frames (base_link -> radar_mount ->
// radar_front, common in real trees) is the chain's product. The offline bag reader and the node
// both read their mountings here, so a bag gives the same mountings read whole or played.
//
// A mounting does not move: each edge (parent -> child) is taken the first time it is seen and
// kept for all times, so it makes no difference whether a transform arrives before or after the
// radar's first message, once on a latched /tf_static (as `rosbag record` stores a static
// transform) or again with every message on /tf.

#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <tf2_msgs/TFMessage.h>

namespace tf2 {
class BufferCore;
}

namespace radar_ndt {
namespace ros1 {

class MountingTree {
 public:
  MountingTree();
  ~MountingTree();
  MountingTree(MountingTree&&) noexcept;
  MountingTree& operator=(MountingTree&&) noexcept;

  /// Takes the transforms of one /tf or /tf_static message (`topic` names it in problems). A
  /// transform whose child already has a parent is left alone; one whose rotation is far from a
  /// unit quaternion, or whose translation is not finite, is left out and said in `problems`.
  void add(const tf2_msgs::TFMessage& message, const std::string& topic, std::vector<std::string>* problems = nullptr);
  /// The transform from `frame` into `base` (a sensor's mounting: points in `frame` to the
  /// vehicle frame) when the tree joins them; nullopt otherwise, `why` then saying what is missing.
  std::optional<Eigen::Isometry3d> lookup(const std::string& base, const std::string& frame,
                                          std::string* why = nullptr) const;
  /// Edges taken so far.
  std::size_t size() const { return children_.size(); }

 private:
  std::unique_ptr<tf2::BufferCore> buffer_;
  std::set<std::string> children_;  ///< frames whose parent is known
};

}  // namespace ros1
}  // namespace radar_ndt

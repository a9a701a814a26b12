#pragma once
/// A robot's kinematics as the joint predictor needs it, without ROS: its movable joints (with
/// their limits), the links they move (with the chain of joints from the root to each and
/// bounds on the lever arms), and forward kinematics. The node implements it with KDL from the
/// URDF (ros/kdl_robot_model.hpp); tests implement it by hand.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace workspace_proximity {

enum class JointType : std::uint8_t {
  kRevolute = 0,    ///< turns about its axis, between limits
  kContinuous = 1,  ///< turns about its axis without limits (positions may wrap)
  kPrismatic = 2,   ///< slides along its axis, between limits
};

struct KinematicJoint {
  std::string name;
  JointType type = JointType::kRevolute;
  bool limited = true;  ///< false for continuous joints
  double lower = 0.0;   ///< rad or m
  double upper = 0.0;   ///< rad or m
};

/// A link moved by at least one joint.
struct KinematicLink {
  std::string name;  ///< its frame (the URDF link name)
  /// Indices (into KinematicModel::joints()) of the movable joints from the root to this link,
  /// root first.
  std::vector<int> chain;
  /// Per chain entry, m: an upper bound, over every joint position, on the distance from the
  /// joint's axis point (the origin of the joint's frame) to this link's origin.
  std::vector<double> reach;
  /// m: the same from the root frame's origin.
  double root_reach = 0.0;
};

class KinematicModel {
 public:
  virtual ~KinematicModel() = default;

  /// The root link: its frame is posed from tf.
  const std::string& root() const { return root_; }
  const std::vector<KinematicJoint>& joints() const { return joints_; }
  /// Links moved by at least one joint (links fixed to the root are not listed).
  const std::vector<KinematicLink>& links() const { return links_; }
  /// Index into joints() / links() by name, or -1.
  int jointIndex(const std::string& name) const;
  int linkIndex(const std::string& name) const;

  /// Pose of every link of links() in the root frame for the joint positions `q` (one per
  /// joints() entry, rad or m), into poses[0 .. links().size()). Allocation-free.
  virtual void forward(const double* q, Eigen::Isometry3d* poses) const = 0;

 protected:
  std::string root_;
  std::vector<KinematicJoint> joints_;
  std::vector<KinematicLink> links_;
};

}  // namespace workspace_proximity

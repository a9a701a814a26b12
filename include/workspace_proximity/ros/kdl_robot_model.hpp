#pragma once
/// The robot's kinematics from its URDF with KDL (kdl_parser): the KinematicModel the joint
/// predictor uses. Every movable joint (revolute, continuous, prismatic) with its URDF limits,
/// every link below at least one of them, and forward kinematics of the whole tree. Needs no
/// master.

#include <memory>
#include <string>
#include <vector>

#include "workspace_proximity/rules/kinematic_model.hpp"

namespace KDL {
class Segment;
}

namespace workspace_proximity {

class KdlRobotModel : public KinematicModel {
 public:
  /// Parses `urdf_xml`. Throws std::runtime_error when it does not parse or KDL refuses it.
  /// Mimic joints and floating or planar joints are not modelled: the links below them are
  /// left out of links() (they keep the tf path).
  explicit KdlRobotModel(const std::string& urdf_xml);
  ~KdlRobotModel() override;

  void forward(const double* q, Eigen::Isometry3d* poses) const override;

 private:
  // The tree in parent-first order: every segment with its parent's entry (-1: the root), its
  // joint's index in joints() (-1: fixed) and its index in links() (-1: not moved).
  struct Entry {
    const KDL::Segment* segment = nullptr;
    int parent = -1;
    int joint = -1;
    int link = -1;
  };
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<Entry> order_;
  mutable std::vector<Eigen::Isometry3d> scratch_;  // per entry, reused
};

}  // namespace workspace_proximity

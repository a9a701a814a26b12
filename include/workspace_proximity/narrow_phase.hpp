#pragma once
/// Narrow phase on the real shapes with FCL: distance now, and a conservative time of first
/// and last contact under constant-twist motion (conservative advancement).

#include <memory>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <fcl/geometry/collision_geometry.h>

#include "workspace_proximity/body.hpp"
#include "workspace_proximity/time_of_impact.hpp"

namespace workspace_proximity {

struct NarrowPhaseConfig {
  /// Conservative advancement declares contact once the gap between the margin-inflated
  /// shapes is at most this, m. Reported contact times are early by at most
  /// distance_tolerance / (closing speed) seconds; never late.
  double distance_tolerance = 1e-5;
  /// Cap on advancement steps per query; reaching it reports contact at the current time
  /// (the safe answer).
  int max_iterations = 200;
};

/// One body as the narrow phase sees it. Pointers are borrowed; they must outlive the query.
struct NarrowBody {
  const fcl::CollisionGeometryd* geometry = nullptr;  ///< from makeGeometry(shape)
  const BodyMotion* motion = nullptr;
  double margin = 0.0;           ///< m
  double bounding_radius = 0.0;  ///< Shape::boundingRadius(), m
};

/// Distance between two posed shapes (without margins).
struct ShapeDistance {
  double distance = 0.0;   ///< m; 0 when touching or overlapping
  bool overlapping = false;
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  ///< nearest point on a, world
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< nearest point on b, world
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  ///< unit, from a towards b
};

/// Result of a contact prediction for one pair.
struct ContactPrediction {
  bool contact = false;          ///< margin-inflated shapes touch somewhere in the window
  double time_to_contact = 0.0;  ///< s, first contact (never later than the truth)
  double time_to_separation = 0.0;  ///< s, last contact within the window (never earlier)
  double distance = 0.0;  ///< gap between the inflated shapes now, m, clamped at 0
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  ///< nearest point on shape a now, world
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< nearest point on shape b now, world
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  ///< unit, from a towards b
  double closing_speed = 0.0;  ///< m/s along the normal at the nearest points, > 0 approaching
  int iterations = 0;          ///< distance queries spent: FCL calls and closed-form ones
};

/// FCL geometry for a shape. Create once per body and reuse: FCL geometries are immutable.
std::shared_ptr<fcl::CollisionGeometryd> makeGeometry(const Shape& shape);

class NarrowPhase {
 public:
  explicit NarrowPhase(const NarrowPhaseConfig& config = NarrowPhaseConfig());

  /// Distance and nearest points between two posed shapes. Every FCL distance is checked
  /// against a lower bound (the gap of the shapes' projections on the reported normal):
  /// FCL 0.7's independent GJK solver is tried first and libccd is the fallback, because
  /// each is occasionally wrong (libccd box-box, fcl#508; independent GJK on ~0.1 % of
  /// rotated box pairs). FCL collide (libccd) gives the contact for overlapping shapes.
  ShapeDistance distance(const fcl::CollisionGeometryd& a, const Eigen::Isometry3d& pose_a,
                         const fcl::CollisionGeometryd& b, const Eigen::Isometry3d& pose_b) const;

  /// Conservative first and last contact of the margin-inflated shapes within `window`
  /// (seconds after t = 0, already clipped to the horizon by the caller). The distance,
  /// nearest points, normal and closing speed describe t = 0 whatever the window.
  ContactPrediction predict(const NarrowBody& a, const NarrowBody& b, TimeInterval window) const;

  const NarrowPhaseConfig& config() const { return config_; }

 private:
  NarrowPhaseConfig config_;
};

}  // namespace workspace_proximity

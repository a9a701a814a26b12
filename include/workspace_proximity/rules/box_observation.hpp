#pragma once
/// One tracked box as a tracker reported it, ROS-free: what the input bridge reads out of a
/// TrackedBox message (views into it, no copies) and what the track table checks and turns
/// into a body.

#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "workspace_proximity/body.hpp"
#include "workspace_proximity/rules/drop.hpp"

namespace workspace_proximity {

/// A box in its array's frame. Numbers are as received (not yet checked).
struct BoxObservation {
  std::string_view id;     ///< unique in its array
  std::string_view label;  ///< class: selects the per-label settings
  Eigen::Vector3d position = Eigen::Vector3d::Zero();           ///< centre, m
  Eigen::Vector4d quaternion = Eigen::Vector4d(0, 0, 0, 1);     ///< x, y, z, w (as received)
  Eigen::Vector3d dimensions = Eigen::Vector3d::Ones();         ///< full edge lengths, m
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();    ///< m/s, in the array's frame
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();   ///< rad/s, in the array's frame
  // The tracker's own uncertainty for this box (issues 23/24). The defaults say "no more than
  // the label's settings", which is what every publisher meant before these fields existed.
  double position_error = 0.0;  ///< m, 3 sigma bound on the centre's error (0: use the label's)
  double velocity_error = 0.0;  ///< m/s, 3 sigma bound on the velocity's error (0: the label's)
  bool velocity_known = true;   ///< false: no velocity yet; grows at the label's max_speed and
                                ///< speed and separation use the label's ssm_min_speed
};

/// Limits on what a tracked box may say before it is rejected as nonsense.
struct BoxLimits {
  double max_dimension = 1000.0;       ///< m, full edge
  double max_coordinate = 1.0e5;       ///< m, |position| in its frame
  double max_speed = 100.0;            ///< m/s
  double max_angular_speed = 100.0;    ///< rad/s
  double quaternion_tolerance = 0.01;  ///< | |q| - 1 | up to this is normalised, beyond rejected
};

/// Drop::kCount when the box is usable; otherwise the reason, with the explanation in
/// `*detail` (built only then). Checks the id, finiteness of every number, dimensions
/// (>= 2 Limits::kMinSize, <= max), coordinates, the tracker's own errors (position_error in
/// [0, max_dimension], velocity_error in [0, max_speed]), the quaternion's length and speeds.
Drop checkBox(const BoxObservation& box, const BoxLimits& limits, std::string* detail);

/// The box's shape (half extents from the full dimensions).
Shape boxShape(const BoxObservation& box);

/// The box's pose and twist in the fixed frame, given the pose of the box's frame in the fixed
/// frame (the twist's vectors are rotated; the frame is assumed not to move). The quaternion
/// is normalised. Call checkBox first.
BodyMotion boxMotion(const BoxObservation& box, const Eigen::Isometry3d& fixed_from_box_frame);

}  // namespace workspace_proximity

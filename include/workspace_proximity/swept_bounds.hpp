#pragma once
/// Conservative bounds of a moving body over the prediction horizon.

#include "workspace_proximity/aabb.hpp"
#include "workspace_proximity/body.hpp"

namespace workspace_proximity {

/// Half extents (m) of an axis-aligned box centred on the body centre that contains the shape
/// in every orientation it takes over [0, horizon], plus the margin.
///
/// Without rotation this is the exact world bound of the shape. Rotating about the fixed
/// world axis k by at most theta = min(|omega| * horizon, pi) moves each column c_i of the
/// rotation matrix by at most the chord 2 sin(theta / 2) |c_i perpendicular to k|, and only
/// perpendicular to k; so world axis j grows by at most
/// chord * sqrt(1 - k_j^2) * sum_i e_i |c_i perpendicular to k| over the rotated local box,
/// capped by the bounding-sphere radius. A body spinning about z keeps its z extent.
Eigen::Vector3d rotationHalfExtents(const Shape& shape, const BodyMotion& motion, double margin,
                                    double horizon);

/// The same from the rotation matrix at t = 0 (`rotation`: motion.orientation.normalized() as a
/// matrix, e.g. motion.poseAt(0).linear()) and the angular velocity (rad/s, world frame), for
/// callers that hold the rotation already. Bit for bit the value of the overload above.
Eigen::Vector3d rotationHalfExtents(const Shape& shape, const Eigen::Matrix3d& rotation,
                                    const Eigen::Vector3d& angular_velocity, double margin,
                                    double horizon);

/// Axis-aligned box (world, m) that contains the body (with margin) at every t in [0, horizon].
/// It is the union of the rotation-inflated box at t = 0 and at t = horizon (the centre
/// moves on a straight line, so the union of the two end boxes covers every box in between).
Aabb sweptBounds(const Shape& shape, const BodyMotion& motion, double margin, double horizon);

/// The same box from the rotation-inflated half extents `half` (m) that rotationHalfExtents()
/// returned for this motion and horizon (s): for callers that keep them anyway.
Aabb sweptBoundsOfHalf(const Eigen::Vector3d& half, const BodyMotion& motion, double horizon);

}  // namespace workspace_proximity

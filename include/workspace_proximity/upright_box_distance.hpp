#pragma once
/// Exact distance between two upright boxes: boxes whose z axis is the world's z axis (up to
/// sign), i.e. rotated about the vertical only. That is what trackers of people, carts and
/// vehicles report, so it is the narrow phase's most common pair.
///
/// An upright box is a vertical prism: its footprint (a rectangle in x-y) times its height
/// interval (in z). For two such products over orthogonal subspaces the squared distance is
/// the sum of the squared footprint distance and the squared height gap, and the distance of
/// two disjoint convex polygons is reached at a vertex of one of them. So the answer is exact
/// (up to rounding) from eight point-rectangle distances, with no iteration. For overlapping
/// boxes the separating axes of two vertical prisms are the four footprint edge normals and
/// z (every edge cross product is one of them), so the least-penetration axis is among five.

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace workspace_proximity {

/// True when `rotation` keeps the z axis vertical: its third row and column are exactly
/// zero off the diagonal (the diagonal entry is then +-1 up to rounding). Quaternions of the
/// form (0, 0, z, w), i.e. yaw only, give this exactly, and so does turning them about z.
/// Inline: every distance query and moving window of two boxes asks it for both poses.
inline bool isUpright(const Eigen::Matrix3d& r) {
  // Zero couplings between z and x-y make the box a vertical prism; r(2, 2) is then +-1 up
  // to the rounding of the quaternion it came from (an upside-down box is upright too).
  return r(0, 2) == 0.0 && r(1, 2) == 0.0 && r(2, 0) == 0.0 && r(2, 1) == 0.0 &&
         std::abs(r(2, 2)) > 0.5;
}

struct UprightBoxDistance {
  /// false: the footprints overlap and no common point could be found for them (a
  /// numerically degenerate touch); the caller must use a general method.
  bool solved = false;
  /// The boxes touch or overlap (distance 0). point_a = point_b is then a point of the
  /// intersection (the centre of the footprints' overlap at mid height of the heights'
  /// overlap) and `normal` the axis of least penetration, pointing from a towards b.
  bool overlapping = false;
  double distance = 0.0;                              ///< m, >= 0
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  ///< nearest point on a, world
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< nearest point on b, world
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  ///< unit, from a towards b
};

/// Distance and nearest points between two upright boxes given by centre pose and half
/// extents (m). Both poses must satisfy isUpright(); the result is meaningless otherwise.
UprightBoxDistance uprightBoxDistance(const Eigen::Isometry3d& pose_a,
                                      const Eigen::Vector3d& half_a,
                                      const Eigen::Isometry3d& pose_b,
                                      const Eigen::Vector3d& half_b);

}  // namespace workspace_proximity

#pragma once
/// Bodies: a rigid shape, its pose and its constant velocity over the prediction horizon.

#include <cstdint>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace workspace_proximity {

/// What the core accepts. Beyond these, bounds could overflow or FCL misbehave (its asserts
/// abort and its solvers can hang on degenerate or astronomically large shapes), so inputs
/// outside them are rejected as invalid instead.
struct Limits {
  static constexpr double kMinSize = 1e-6;        ///< m, smallest half extent / radius / length
  static constexpr double kMaxSize = 1e4;         ///< m, largest half extent / radius / length
  static constexpr double kMaxMargin = 1e3;       ///< m
  static constexpr double kMaxCoordinate = 1e7;   ///< m, |position| on any axis
  static constexpr double kMaxSpeed = 1e4;        ///< m/s
  static constexpr double kMaxAngularSpeed = 1e4; ///< rad/s
  static constexpr double kMaxHorizon = 1e4;      ///< s
  static constexpr double kMaxAccel = 1e4;        ///< m/s^2, margin growth (MarginGrowth)
  static constexpr int kMaxSegments = 64;         ///< segments of a piecewise path (setPath)
};

/// The shapes the narrow phase understands. Every shape is centred on the body origin;
/// cylinders and capsules have their axis along the body's local z.
enum class ShapeType : std::uint8_t { kBox = 0, kSphere = 1, kCylinder = 2, kCapsule = 3 };

/// Shape dimensions, metres.
struct Shape {
  ShapeType type = ShapeType::kBox;
  /// Box: half extents along local x, y, z. Other shapes ignore it.
  Eigen::Vector3d half_extents = Eigen::Vector3d::Constant(0.5);
  /// Sphere, cylinder, capsule: radius.
  double radius = 0.0;
  /// Cylinder: full length of the side; capsule: length of the segment between the two
  /// hemisphere centres (total length is length + 2 radius).
  double length = 0.0;

  static Shape box(const Eigen::Vector3d& half_extents);
  static Shape sphere(double radius);
  static Shape cylinder(double radius, double length);
  static Shape capsule(double radius, double length);

  /// Half extents of the shape's own bounding box in its local frame.
  Eigen::Vector3d localHalfExtents() const;
  /// Largest distance from the body origin to any point of the shape (bounding sphere).
  double boundingRadius() const;
  /// True when every dimension is within [Limits::kMinSize, Limits::kMaxSize] (a capsule's
  /// length may also be 0: it is then a sphere).
  bool valid() const;
};

/// True when a safety margin (m) is finite and within [0, Limits::kMaxMargin].
bool validMargin(double margin);

/// Which side of the robot/world divide a body is on; pair rules use it.
enum class BodyGroup : std::uint8_t { kRobot = 0, kObject = 1 };

/// Every component exactly zero (a NaN is not): a body whose angular velocity this is does
/// not turn. What Eigen's isZero(0.0) answers, without its per-coefficient loop.
inline bool isExactlyZero(const Eigen::Vector3d& v) {
  return v.x() == 0.0 && v.y() == 0.0 && v.z() == 0.0;
}

/// Pose and constant velocity of a body at the prediction instant (t = 0).
/// Motion model over [0, H]: centre(t) = position + linear_velocity * t,
/// orientation(t) = exp(angular_velocity * t) * orientation (angular velocity in the world frame).
struct BodyMotion {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();                 ///< centre, m
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();    ///< unit quaternion
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();          ///< m/s, world frame
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();         ///< rad/s, world frame

  /// Pose at time t (seconds) under the constant-twist model above.
  Eigen::Isometry3d poseAt(double t) const;
  /// The same motion moved dt seconds along itself (latency compensation): pose at dt,
  /// velocities unchanged. dt may be negative.
  BodyMotion advanced(double dt) const;
  /// True when every number is finite and within Limits, and the quaternion is unit length
  /// within 1e-6.
  bool valid() const;
};

/// Handle of a body in a ProximityWorld: a slot index plus a generation that changes
/// whenever the slot is reused, so a stale handle is detected instead of aliasing a new body.
struct BodyHandle {
  std::int32_t index = -1;
  std::uint32_t generation = 0;
  bool operator==(const BodyHandle& o) const { return index == o.index && generation == o.generation; }
  bool operator!=(const BodyHandle& o) const { return !(*this == o); }
};

struct PathSegment;   // motion_path.hpp
struct MarginGrowth;  // motion_path.hpp

/// A body as the per-pair stages (contact window, narrow phase) see it. Pointers are
/// borrowed for the call.
struct PairBody {
  const Shape* shape = nullptr;
  const BodyMotion* motion = nullptr;
  double margin = 0.0;  ///< safety margin around the shape, m
  /// Contact window: half extents (m) of an axis-aligned box around the centre that holds the
  /// shape and margin in every orientation over the horizon (rotationHalfExtents()).
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
  /// Narrow phase: the slot of the shape's FCL geometry in its cache (NarrowPhase::setShape),
  /// or -1 to build the geometry for this query alone (allocates: for tests and one-off use).
  std::int32_t geometry = -1;
  /// The pose at t = 0 (motion->poseAt(0)) if the caller has it, so that the stages need not
  /// compute it again; nullptr: computed where needed.
  const Eigen::Isometry3d* pose = nullptr;
  /// Piecewise motion (motion_path.hpp): the prepared segments of the body's path
  /// (preparePath; segments[0].motion is *motion), or null for the constant twist `motion`
  /// with `margin` and `half`.
  const PathSegment* segments = nullptr;
  int segment_count = 0;
  /// The body's margin growth, or null when it does not grow.
  const MarginGrowth* growth = nullptr;

  /// Needs the piecewise stages (PairPieces): a path or a growing margin.
  bool piecewise() const { return segments != nullptr || growth != nullptr; }

  /// The pose at t = 0: *pose, or motion->poseAt(0) written into `scratch`.
  const Eigen::Isometry3d& poseNow(Eigen::Isometry3d* scratch) const {
    if (pose != nullptr) return *pose;
    *scratch = motion->poseAt(0.0);
    return *scratch;
  }
};

/// Everything that describes a body except its motion.
struct BodyDesc {
  std::string id;            ///< caller's identifier, unique among live bodies
  std::string label;         ///< class: "person", "forklift", "robot", ...
  BodyGroup group = BodyGroup::kObject;
  Shape shape;
  double margin = 0.0;       ///< safety margin added around the shape, m (>= 0)
};

}  // namespace workspace_proximity

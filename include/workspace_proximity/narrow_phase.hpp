#pragma once
/// Narrow phase on the real shapes: distance now, and a conservative time of first and last
/// contact under constant-twist motion (conservative advancement) inside the window the
/// contact-window stage gives it. FCL answers for the shapes without a closed form; its
/// geometry is a private cache of this class (no FCL type in this header).

#include <cstdint>
#include <memory>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "workspace_proximity/body.hpp"
#include "workspace_proximity/contact_window.hpp"

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

class NarrowPhase {
 public:
  explicit NarrowPhase(const NarrowPhaseConfig& config = NarrowPhaseConfig());
  ~NarrowPhase();
  NarrowPhase(NarrowPhase&&) noexcept;
  NarrowPhase& operator=(NarrowPhase&&) noexcept;

  /// Builds and keeps the FCL geometry of `shape` in slot `slot` (>= 0; the world uses its
  /// body slots), replacing what the slot held. Queries naming the slot (PairBody::geometry)
  /// then allocate nothing. Throws std::invalid_argument on an invalid shape.
  void setShape(std::int32_t slot, const Shape& shape);
  /// Frees the slot's geometry.
  void clearShape(std::int32_t slot);

  /// Distance and nearest points between two posed shapes (builds their FCL geometry for the
  /// call). Upright boxes (turned about z only) have a closed form; other pairs go to FCL,
  /// whose every distance is checked against a lower bound (the gap of the shapes'
  /// projections on the reported normal): FCL 0.7's independent GJK solver is tried first
  /// and libccd is the fallback, because each is occasionally wrong (libccd box-box, fcl#508;
  /// independent GJK on ~0.1 % of rotated box pairs). FCL collide (libccd) gives the contact
  /// for overlapping shapes.
  ShapeDistance distance(const Shape& a, const Eigen::Isometry3d& pose_a, const Shape& b,
                         const Eigen::Isometry3d& pose_b) const;

  /// Distance and nearest points between two bodies' bare shapes (margins not included) at
  /// t = 0, from their cached geometry (PairBody::geometry) and pose now: allocation-free for
  /// separated shapes. Overlapping shapes get distance 0, a common point and the contact normal.
  ShapeDistance distanceNow(const PairBody& a, const PairBody& b) const;

  /// Conservative first and last contact of the margin-inflated shapes (shape, motion and
  /// margin of each body are read) inside `window` (from contactWindow() or refineWindow()):
  /// an exact window is taken as it is, otherwise advancement refines its first contact and,
  /// unless the window's end is already known to be the last one, its last contact. The
  /// distance, nearest points, normal and closing speed describe t = 0 whatever the window.
  ///
  /// Bodies with a path or a growing margin (PairBody::piecewise()) need a window from
  /// piecewiseWindow() (otherwise std::invalid_argument): the advancement then runs piece by
  /// piece (PairPieces), each piece with its own segments' twists and margins, and adds both
  /// growth rates at their largest on the piece to the closing-speed bound, so it still never
  /// steps over a contact. Newton steps are used only on pieces where the gap is convex (both
  /// bodies translating, growth linear); the upright closed form serves every evaluation. The
  /// first contact is that of the grown shapes; the last contact is that of the shapes without
  /// growth (their segment margins only), never before the first contact, and equal to it when
  /// they never touch. The distance now includes the growth since each observation.
  ContactPrediction predict(const PairBody& a, const PairBody& b,
                            const ContactWindow& window) const;

  const NarrowPhaseConfig& config() const { return config_; }

 private:
  struct GeometryCache;  // FCL geometry by slot

  ContactPrediction predictOnPieces(const PairBody& a, const PairBody& b,
                                    const ContactWindow& window) const;

  NarrowPhaseConfig config_;
  std::unique_ptr<GeometryCache> cache_;
};

}  // namespace workspace_proximity

#pragma once
/// The self-filter: which cloud points are the robot's own. A point is the robot's when it
/// lies inside a link's shape grown by padding + (bound on the link's point speed) x |cloud
/// stamp - pose stamp|: however the link moved in between (at most that fast), its surface
/// is within that distance of the posed shape. Points within `near_band` outside every grown
/// link are counted: many of them mean the padding, the calibration or the timing is off.
/// ROS-free; allocation-free after construction.

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "workspace_proximity/aabb.hpp"
#include "workspace_proximity/body.hpp"

namespace workspace_proximity {
namespace perception {

/// One robot link as the self-filter sees it.
struct SelfLink {
  Shape shape;                                                ///< box, sphere, cylinder, capsule
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();     ///< shape pose, fixed frame, at the pose stamp
  double speed = 0.0;  ///< m/s, bound on the speed of any point of the link (linkSpeedBound)
  /// s: this link's own |cloud stamp - pose stamp| (links posed from different readings);
  /// negative: the common `stamp_offset` of setLinks. Not a number: refused.
  double gap = -1.0;
};

/// m/s: |v| + |w| x the shape's bounding radius, a bound on the speed of every point of a
/// body moving by `motion` (its centre at the shape's origin).
double linkSpeedBound(const BodyMotion& motion, const Shape& shape);

/// m: distance from `p` (in the shape's own frame) to the shape; 0 inside.
double shapeDistance(const Shape& shape, const Eigen::Vector3d& p);
float shapeDistance(const Shape& shape, const Eigen::Vector3f& p);

/// What a point is to the robot.
enum class SelfVerdict : std::uint8_t {
  kClear = 0,  ///< farther than growth + near_band from every link
  kNear = 1,   ///< outside every grown link, within near_band of one
  kSelf = 2,   ///< inside a grown link: the robot's own point
};

class SelfFilter {
 public:
  explicit SelfFilter(int max_links);

  /// The robot for the next cloud(s). `stamp_offset`: s, cloud stamp - pose stamp (either
  /// sign); `padding`, `near_band`: m. Returns false (and keeps no links: nothing is
  /// filtered) when there are more than max_links links, a shape is invalid or a number is
  /// not finite / negative.
  bool setLinks(const SelfLink* links, int count, double padding, double stamp_offset,
                double near_band);

  int count() const { return count_; }
  /// m: how far link i is grown (padding + speed x its gap, or |stamp_offset| without one).
  double growth(int i) const { return grow_[static_cast<std::size_t>(i)]; }
  /// Box holding every grown link plus the near band (empty when there are no links).
  const Aabb& bounds() const { return bounds_; }

  /// The verdict for a point in the fixed frame.
  SelfVerdict classify(const Eigen::Vector3f& p) const;

 private:
  struct Link {
    Shape shape;
    Eigen::Matrix3f to_local;      // rotation fixed -> shape frame
    Eigen::Vector3f origin;        // shape origin, fixed frame
    Eigen::Vector3f lower, upper;  // grown + band bounds, fixed frame
    float grow = 0.0f;
    float reach = 0.0f;            // grow + band
  };
  int max_links_;
  int count_ = 0;
  std::vector<Link> links_;
  std::vector<double> grow_;
  Aabb bounds_;
  bool any_ = false;
};

}  // namespace perception
}  // namespace workspace_proximity

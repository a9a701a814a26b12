#include "workspace_proximity/perception/self_filter.hpp"

#include "shape_distance.hpp"

#include <algorithm>
#include <cmath>

namespace workspace_proximity {
namespace perception {


double shapeDistance(const Shape& shape, const Eigen::Vector3d& p) { return shapeDistanceT(shape, p); }
float shapeDistance(const Shape& shape, const Eigen::Vector3f& p) { return shapeDistanceT(shape, p); }

double linkSpeedBound(const BodyMotion& motion, const Shape& shape) {
  return motion.linear_velocity.norm() + motion.angular_velocity.norm() * shape.boundingRadius();
}

SelfFilter::SelfFilter(int max_links) : max_links_(std::max(0, max_links)) {
  links_.resize(static_cast<std::size_t>(max_links_));
  grow_.resize(static_cast<std::size_t>(max_links_));
}

bool SelfFilter::setLinks(const SelfLink* links, int count, double padding, double stamp_offset,
                          double near_band) {
  count_ = 0;
  any_ = false;
  bounds_ = Aabb{};
  if (count < 0 || count > max_links_ || (count > 0 && links == nullptr)) return false;
  if (!std::isfinite(padding) || padding < 0.0 || !std::isfinite(stamp_offset) ||
      !std::isfinite(near_band) || near_band < 0.0) {
    return false;
  }
  for (int i = 0; i < count; ++i) {
    const SelfLink& in = links[i];
    if (!in.shape.valid() || !std::isfinite(in.speed) || in.speed < 0.0 ||
        !in.pose.matrix().allFinite() || !std::isfinite(in.gap)) {
      count_ = 0;
      return false;
    }
    // A link posed from its own reading (joint states) has its own gap to the cloud's stamp.
    const double gap = in.gap >= 0.0 ? in.gap : std::abs(stamp_offset);
    const double grow = padding + in.speed * gap;
    const Eigen::Matrix3d rot = in.pose.linear();
    const Eigen::Vector3d half =
        rot.cwiseAbs() * in.shape.localHalfExtents() + Eigen::Vector3d::Constant(grow + near_band);
    const Eigen::Vector3d centre = in.pose.translation();
    Link& l = links_[static_cast<std::size_t>(i)];
    l.shape = in.shape;
    l.to_local = rot.transpose().cast<float>();
    l.origin = centre.cast<float>();
    // Bounds rounded outwards by a hair: the float test must never miss a point the double
    // geometry holds.
    l.lower = (centre - half).cast<float>() - Eigen::Vector3f::Constant(1e-4f);
    l.upper = (centre + half).cast<float>() + Eigen::Vector3f::Constant(1e-4f);
    l.grow = static_cast<float>(grow);
    l.reach = static_cast<float>(grow + near_band);
    grow_[static_cast<std::size_t>(i)] = grow;
    const Aabb box{l.lower.cast<double>(), l.upper.cast<double>()};
    bounds_ = any_ ? bounds_.merged(box) : box;
    any_ = true;
  }
  count_ = count;
  return true;
}

SelfVerdict SelfFilter::classify(const Eigen::Vector3f& p) const {
  if (!any_) return SelfVerdict::kClear;
  SelfVerdict verdict = SelfVerdict::kClear;
  for (int i = 0; i < count_; ++i) {
    const Link& l = links_[static_cast<std::size_t>(i)];
    if ((p.array() < l.lower.array()).any() || (p.array() > l.upper.array()).any()) continue;
    const float d = shapeDistanceT(l.shape, Eigen::Vector3f(l.to_local * (p - l.origin)));
    if (d <= l.grow) return SelfVerdict::kSelf;
    if (d <= l.reach) verdict = SelfVerdict::kNear;
  }
  return verdict;
}

}  // namespace perception
}  // namespace workspace_proximity

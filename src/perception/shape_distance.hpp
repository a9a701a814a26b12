#pragma once
// Private to src/perception: the distance from a point to a shape, inlined where it is hot
// (the self-filter's points, the unseen share's protective voxels).

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "workspace_proximity/body.hpp"

namespace workspace_proximity {
namespace perception {

// Distance from p (shape frame) to the shape, 0 inside; exact for every shape type, so that
// the grown shape is the true Minkowski sum with a ball (what "within g of the link" means).
template <typename T>
inline T shapeDistanceT(const Shape& s, const Eigen::Matrix<T, 3, 1>& p) {
  switch (s.type) {
    case ShapeType::kBox: {
      const Eigen::Matrix<T, 3, 1> q =
          (p.cwiseAbs() - s.half_extents.cast<T>()).cwiseMax(T(0));
      return q.norm();
    }
    case ShapeType::kSphere:
      return std::max(p.norm() - T(s.radius), T(0));
    case ShapeType::kCylinder: {
      const T radial = std::max(std::hypot(p.x(), p.y()) - T(s.radius), T(0));
      const T axial = std::max(std::abs(p.z()) - T(0.5 * s.length), T(0));
      return std::hypot(radial, axial);
    }
    case ShapeType::kCapsule: {
      const T h = T(0.5 * s.length);
      const T z = std::min(std::max(p.z(), -h), h);
      const Eigen::Matrix<T, 3, 1> d(p.x(), p.y(), p.z() - z);
      return std::max(d.norm() - T(s.radius), T(0));
    }
  }
  return T(0);
}


}  // namespace perception
}  // namespace workspace_proximity

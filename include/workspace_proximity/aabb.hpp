#pragma once
/// Axis-aligned bounding boxes in double precision (metres).

#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace workspace_proximity {

/// Closed axis-aligned box [lower, upper] in world coordinates, metres.
/// Two boxes that share only a face, edge or corner overlap (closed intervals):
/// touching counts as contact everywhere in this library.
struct Aabb {
  Eigen::Vector3d lower = Eigen::Vector3d::Zero();
  Eigen::Vector3d upper = Eigen::Vector3d::Zero();

  /// True when the closed boxes share at least one point.
  bool overlaps(const Aabb& other) const {
    return (lower.array() <= other.upper.array()).all() &&
           (other.lower.array() <= upper.array()).all();
  }

  /// Smallest box containing both.
  Aabb merged(const Aabb& other) const {
    return Aabb{lower.cwiseMin(other.lower), upper.cwiseMax(other.upper)};
  }

  /// True when every component is finite and lower <= upper on every axis. (Written out
  /// without Eigen's reductions or branches: the broad phase checks every moved box with it.
  /// -inf < lower <= upper < +inf says the same: a NaN fails every comparison, and an
  /// infinite bound fails the strict ones.)
  bool valid() const {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      const double lo = lower[k], hi = upper[k];  // (plain values: no call in the & chain)
      ok &= (-kInf < lo) & (lo <= hi) & (hi < kInf);
    }
    return ok;
  }
};

}  // namespace workspace_proximity

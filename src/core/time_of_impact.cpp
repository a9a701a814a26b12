#include "workspace_proximity/time_of_impact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "workspace_proximity/upright_box_distance.hpp"

namespace workspace_proximity {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Pushes an interval end outward by a few ulps plus a picosecond: one division and one
// subtraction each round once, so this is enough to never lose a touching instant.
double widenDown(double t) { return t - (std::abs(t) * 4.0 * std::numeric_limits<double>::epsilon() + 1e-12); }
double widenUp(double t) { return t + (std::abs(t) * 4.0 * std::numeric_limits<double>::epsilon() + 1e-12); }

}  // namespace

TimeInterval axisContactInterval(double lo_a, double hi_a, double v_a, double lo_b, double hi_b,
                                 double v_b) {
  // Overlap at t  <=>  lo_a + v_a t <= hi_b + v_b t  and  lo_b + v_b t <= hi_a + v_a t.
  // With dv = v_a - v_b:  dv t <= hi_b - lo_a  and  dv t >= lo_b - hi_a.
  const double dv = v_a - v_b;
  const double gap_ahead = hi_b - lo_a;  // how far a may advance before its lower passes b's upper
  const double gap_behind = lo_b - hi_a; // how far a must advance to reach b's lower
  if (dv == 0.0) {
    // No relative motion: the overlap state never changes.
    if (gap_behind <= 0.0 && gap_ahead >= 0.0) return TimeInterval{-kInf, kInf};
    return TimeInterval{};
  }
  double first, last;
  if (dv > 0.0) {
    first = gap_behind / dv;
    last = gap_ahead / dv;
  } else {
    first = gap_ahead / dv;
    last = gap_behind / dv;
  }
  return TimeInterval{widenDown(first), widenUp(last)};
}

TimeInterval boxContactInterval(const Eigen::Vector3d& center_a, const Eigen::Vector3d& half_a,
                                const Eigen::Vector3d& velocity_a,
                                const Eigen::Vector3d& center_b, const Eigen::Vector3d& half_b,
                                const Eigen::Vector3d& velocity_b, double horizon) {
  TimeInterval result{0.0, std::max(horizon, 0.0)};
  for (int k = 0; k < 3; ++k) {
    const TimeInterval axis =
        axisContactInterval(center_a[k] - half_a[k], center_a[k] + half_a[k], velocity_a[k],
                            center_b[k] - half_b[k], center_b[k] + half_b[k], velocity_b[k]);
    result.first = std::max(result.first, axis.first);
    result.last = std::min(result.last, axis.last);
    if (result.empty()) return TimeInterval{};
  }
  return result;
}

TimeInterval movingBoxInterval(const Eigen::Isometry3d& pose_a, const Eigen::Vector3d& half_a,
                               const Eigen::Vector3d& velocity_a,
                               const Eigen::Isometry3d& pose_b, const Eigen::Vector3d& half_b,
                               const Eigen::Vector3d& velocity_b, double inflation,
                               TimeInterval window) {
  const Eigen::Matrix3d ra = pose_a.linear();
  const Eigen::Matrix3d rb = pose_b.linear();
  const Eigen::Vector3d offset = pose_b.translation() - pose_a.translation();
  const Eigen::Vector3d dv = velocity_b - velocity_a;
  TimeInterval result = window;

  // On axis l, b's centre moves relative to a's at l.dv along l; they overlap while the
  // gap between the centres is within the sum of the two supports.
  auto clip = [&](const Eigen::Vector3d& l) {
    const double support_a = half_a.dot((ra.transpose() * l).cwiseAbs()) + inflation;
    const double support_b = half_b.dot((rb.transpose() * l).cwiseAbs());
    const double c = l.dot(offset);
    const TimeInterval axis = axisContactInterval(-support_a, support_a, 0.0, c - support_b,
                                                  c + support_b, l.dot(dv));
    result.first = std::max(result.first, axis.first);
    result.last = std::min(result.last, axis.last);
  };
  if (isUpright(ra) && isUpright(rb)) {
    // Two vertical prisms: every edge cross product is z or a footprint normal, so these
    // five axes are the whole separating-axis set.
    for (int i = 0; i < 2 && !result.empty(); ++i) clip(ra.col(i));
    for (int i = 0; i < 2 && !result.empty(); ++i) clip(rb.col(i));
    if (!result.empty()) clip(Eigen::Vector3d::UnitZ());
    return result.empty() ? TimeInterval{} : result;
  }
  for (int i = 0; i < 3 && !result.empty(); ++i) clip(ra.col(i));
  for (int i = 0; i < 3 && !result.empty(); ++i) clip(rb.col(i));
  for (int i = 0; i < 3 && !result.empty(); ++i) {
    for (int j = 0; j < 3 && !result.empty(); ++j) {
      const Eigen::Vector3d l = ra.col(i).cross(rb.col(j));
      const double norm = l.norm();
      if (norm > 1e-6) clip(l / norm);  // unit, so `inflation` means metres on every axis
    }
  }
  return result.empty() ? TimeInterval{} : result;
}

}  // namespace workspace_proximity

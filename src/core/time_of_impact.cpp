#include "workspace_proximity/time_of_impact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

}  // namespace workspace_proximity

#include "workspace_proximity/time_of_impact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "workspace_proximity/upright_box_distance.hpp"

namespace workspace_proximity {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Smallest x >= 0 at which the convex f(x) = a x^2 + b x + c (a >= 0, c = f(0) < 0) is back
// at 0: its larger root (the roots straddle 0 when a > 0). +infinity when it never is.
double exitRoot(double a, double b, double c) {
  if (a > 0.0) {
    const double root = std::sqrt(b * b - 4.0 * a * c);
    // The cancellation-free form of each sign of b.
    return b <= 0.0 ? (-b + root) / (2.0 * a) : (-2.0 * c) / (b + root);
  }
  return b > 0.0 ? -c / b : kInf;
}

// Largest x <= 0 at which the convex f (f(0) = c < 0) was last at 0: its smaller root.
// -infinity when it never was.
double entryRoot(double a, double b, double c) {
  if (a > 0.0) {
    const double root = std::sqrt(b * b - 4.0 * a * c);
    return b >= 0.0 ? (-b - root) / (2.0 * a) : (2.0 * c) / (-b + root);
  }
  return b < 0.0 ? -c / b : -kInf;
}

}  // namespace

TimeInterval growingAxisInterval(double centre_a, double half_a, double v_a, const double grow_a[3],
                                 double centre_b, double half_b, double v_b, const double grow_b[3],
                                 double length) {
  // Overlap at x  <=>  |D(x)| <= S(x), D = centre_b - centre_a (linear), S = the sum of the
  // half widths (convex). f_up = S - D >= 0 (b's lower end below a's upper end) and
  // f_down = S + D >= 0; f_up + f_down = 2 S > 0, so they are never negative together.
  const double d0 = centre_b - centre_a;
  const double dv = v_b - v_a;
  const double s0 = half_a + half_b + grow_a[0] + grow_b[0];
  const double s1 = grow_a[1] + grow_b[1];
  const double s2 = grow_a[2] + grow_b[2];
  // A slack of a few ulps of the terms, so that a touching instant is never lost to rounding.
  const double slack = 8.0 * std::numeric_limits<double>::epsilon() * (std::abs(s0) + std::abs(d0)) + 1e-15;
  const double up[3] = {s0 + slack - d0, s1 - dv, s2};
  const double down[3] = {s0 + slack + d0, s1 + dv, s2};
  auto value = [](const double f[3], double x) { return f[0] + x * (f[1] + x * f[2]); };
  const double end = std::max(length, 0.0);

  // First instant: 0 unless a condition fails there; then where that one recovers.
  double first = 0.0;
  const double* failing = up[0] < 0.0 ? up : (down[0] < 0.0 ? down : nullptr);
  if (failing != nullptr) {
    first = widenDown(exitRoot(failing[2], failing[1], failing[0]));
    if (!(first <= end)) return TimeInterval{};
    first = std::max(first, 0.0);
  }
  // Last instant: the end unless a condition fails there; then where that one started failing
  // (in y = x - end: f(end + y) = a y^2 + (b + 2 a end) y + f(end)).
  double last = end;
  const double at_end_up = value(up, end), at_end_down = value(down, end);
  const double* failing_end = at_end_up < 0.0 ? up : (at_end_down < 0.0 ? down : nullptr);
  if (failing_end != nullptr) {
    const double c = failing_end == up ? at_end_up : at_end_down;
    last = end + widenUp(entryRoot(failing_end[2], failing_end[1] + 2.0 * failing_end[2] * end, c));
    if (!(last >= 0.0)) return TimeInterval{};
    last = std::min(last, end);
  }
  if (last < first) last = first;  // rounding at a single touching instant: keep it
  return TimeInterval{first, last};
}

namespace {

// axisContactInterval, inlined into the per-pair stages below (they call it up to 8 times a
// pair).
inline TimeInterval axisInterval(double lo_a, double hi_a, double v_a, double lo_b, double hi_b,
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

}  // namespace

TimeInterval axisContactInterval(double lo_a, double hi_a, double v_a, double lo_b, double hi_b,
                                 double v_b) {
  return axisInterval(lo_a, hi_a, v_a, lo_b, hi_b, v_b);
}

TimeInterval boxContactInterval(const Eigen::Vector3d& center_a, const Eigen::Vector3d& half_a,
                                const Eigen::Vector3d& velocity_a,
                                const Eigen::Vector3d& center_b, const Eigen::Vector3d& half_b,
                                const Eigen::Vector3d& velocity_b, double horizon) {
  TimeInterval result{0.0, std::max(horizon, 0.0)};
  for (int k = 0; k < 3; ++k) {
    const TimeInterval axis =
        axisInterval(center_a[k] - half_a[k], center_a[k] + half_a[k], velocity_a[k],
                            center_b[k] - half_b[k], center_b[k] + half_b[k], velocity_b[k]);
    result.first = std::max(result.first, axis.first);
    result.last = std::min(result.last, axis.last);
    if (result.empty()) return TimeInterval{};
  }
  return result;
}

namespace {

// Narrows `result` to the times at which two intervals overlap on one axis: a's centred at 0
// with half width support_a, b's centred at c with half width support_b and moving at `speed`
// relative to a along the axis.
inline void clipOnAxis(double support_a, double support_b, double c, double speed,
                       TimeInterval* result) {
  const TimeInterval axis =
      axisInterval(-support_a, support_a, 0.0, c - support_b, c + support_b, speed);
  result->first = std::max(result->first, axis.first);
  result->last = std::min(result->last, axis.last);
}

// Half width of an upright box's footprint (axes `u`, `v` of its rotation, half sizes hu, hv)
// projected on the horizontal axis `l`; its z axis is perpendicular to l.
inline double footprintSupport(const Eigen::Matrix3d& r, double hu, double hv,
                               const Eigen::Vector3d& l) {
  return hu * std::abs(r(0, 0) * l.x() + r(1, 0) * l.y()) +
         hv * std::abs(r(0, 1) * l.x() + r(1, 1) * l.y());
}

// movingBoxInterval for two vertical prisms: every edge cross product is z or a footprint
// normal, so a's two footprint normals, b's two and z are the whole separating-axis set. On
// its own footprint normal a box's support is its half size there, the other box's comes from
// its footprint alone; on z both are their half heights.
TimeInterval uprightMovingInterval(const Eigen::Matrix3d& ra, const Eigen::Vector3d& half_a,
                                   const Eigen::Matrix3d& rb, const Eigen::Vector3d& half_b,
                                   const Eigen::Vector3d& offset, const Eigen::Vector3d& dv,
                                   double inflation, TimeInterval result) {
  for (int i = 0; i < 2 && !result.empty(); ++i) {
    const Eigen::Vector3d l(ra(0, i), ra(1, i), 0.0);
    clipOnAxis(half_a[i] + inflation, footprintSupport(rb, half_b.x(), half_b.y(), l),
               l.x() * offset.x() + l.y() * offset.y(), l.x() * dv.x() + l.y() * dv.y(), &result);
  }
  for (int i = 0; i < 2 && !result.empty(); ++i) {
    const Eigen::Vector3d l(rb(0, i), rb(1, i), 0.0);
    clipOnAxis(footprintSupport(ra, half_a.x(), half_a.y(), l) + inflation, half_b[i],
               l.x() * offset.x() + l.y() * offset.y(), l.x() * dv.x() + l.y() * dv.y(), &result);
  }
  if (!result.empty()) clipOnAxis(half_a.z() + inflation, half_b.z(), offset.z(), dv.z(), &result);
  return result.empty() ? TimeInterval{} : result;
}

}  // namespace

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
    clipOnAxis(support_a, support_b, l.dot(offset), l.dot(dv), &result);
  };
  if (isUpright(ra) && isUpright(rb)) {
    return uprightMovingInterval(ra, half_a, rb, half_b, offset, dv, inflation, result);
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

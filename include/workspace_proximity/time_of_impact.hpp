#pragma once
/// Per-axis time of first and last contact of two translating axis-aligned boxes
/// (the lecture's "time = distance / velocity" test, on three axes).

#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace workspace_proximity {

/// A closed time interval in seconds; empty when first > last.
struct TimeInterval {
  double first = 1.0;
  double last = 0.0;
  bool empty() const { return !(first <= last); }
};

/// An interval end (s) pushed outward by 4 ulps plus a picosecond: a division and a
/// subtraction each round once, so this never loses a touching instant. Every interval of
/// this header and of the contact-window stage is widened with these.
inline double widenDown(double t) {
  return t - (std::abs(t) * 4.0 * std::numeric_limits<double>::epsilon() + 1e-12);
}
inline double widenUp(double t) {
  return t + (std::abs(t) * 4.0 * std::numeric_limits<double>::epsilon() + 1e-12);
}

/// Times at which the closed 1-D intervals [lo_a + v_a t, hi_a + v_a t] and
/// [lo_b + v_b t, hi_b + v_b t] overlap, over all real t. Unbounded sides are +-infinity;
/// the result is empty when they never meet. Each end is widened outward by 4 ulps plus
/// 1 ps, so floating-point rounding never makes it narrower than the exact interval.
TimeInterval axisContactInterval(double lo_a, double hi_a, double v_a, double lo_b, double hi_b,
                                 double v_b);

/// The same on a stretch x in [0, length] (s) where each interval also grows on both sides by
/// a polynomial of degree at most 2 with a non-negative leading coefficient (a growing margin):
/// a's interval is centre_a + v_a x -+ (half_a + grow_a(x)), b's likewise, grow(x) =
/// g0 + g1 x + g2 x^2 (grow_a and grow_b each {g0, g1, g2}). Both overlap conditions are
/// convex quadratics in x, at most one of them negative at a time, so the overlapping instants
/// are [0, length] less at most two open intervals; returned is their hull (first and last
/// overlapping instant, from the roots in closed form), empty when there is none. Constants
/// get a relative slack of a few ulps and the roots are widened like axisContactInterval's,
/// so rounding never narrows it. half_a + half_b must be > 0.
TimeInterval growingAxisInterval(double centre_a, double half_a, double v_a, const double grow_a[3],
                                 double centre_b, double half_b, double v_b, const double grow_b[3],
                                 double length);

/// Conservative contact interval of two boxes, each centred at `center` with half extents
/// `half` (m) and translating at `velocity` (m/s): the intersection of the three per-axis
/// intervals clipped to [0, horizon]. Empty means "no contact within the horizon".
TimeInterval boxContactInterval(const Eigen::Vector3d& center_a, const Eigen::Vector3d& half_a,
                                const Eigen::Vector3d& velocity_a,
                                const Eigen::Vector3d& center_b, const Eigen::Vector3d& half_b,
                                const Eigen::Vector3d& velocity_b, double horizon);

/// Contact interval of two oriented boxes translating at constant velocities (no rotation),
/// clipped to `window`: the separating-axis test on the 15 candidate axes (3 face normals of
/// each box and the 9 edge cross products), each axis a 1-D moving-interval problem solved
/// with axisContactInterval, intersected. Exact for inflation = 0. With inflation > 0 each
/// box's support on every axis grows by that much, which contains every instant at which
/// the boxes grown by a ball of radius `inflation` (the margins) touch: never late, never
/// short. Edge axes of nearly parallel edges are skipped, which can only widen the result.
TimeInterval movingBoxInterval(const Eigen::Isometry3d& pose_a, const Eigen::Vector3d& half_a,
                               const Eigen::Vector3d& velocity_a,
                               const Eigen::Isometry3d& pose_b, const Eigen::Vector3d& half_b,
                               const Eigen::Vector3d& velocity_b, double inflation,
                               TimeInterval window);

}  // namespace workspace_proximity

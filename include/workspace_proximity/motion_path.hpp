#pragma once
/// Motion beyond one constant twist: a body may follow a piecewise constant-twist path over the
/// horizon (keyframes, e.g. a robot link sampled along its joints' motion), and its margin may
/// grow with time (the bounded uncertainty of a tracked object). Both are optional: a body with
/// one segment and no growth is predicted exactly as before, bit for bit.

#include <limits>

#include <Eigen/Core>

#include "workspace_proximity/aabb.hpp"
#include "workspace_proximity/body.hpp"

namespace workspace_proximity {

/// A margin that grows with time, m(t) = m_0 + R(age + t), where t is seconds after the
/// prediction instant and
///   R(s) = min(e s + a s^2 / 2, c s)  (s >= 0),
/// the set-based bound on where an object measured at c with velocity v can be s seconds after
/// the measurement when its velocity error is at most e and its acceleration at most a, and
/// its speed at most v_max (then c = v_max + |v|, since it can leave the nominal path no
/// faster than that). R(0) = 0 and R is non-decreasing. `age` is how long before the prediction
/// instant the object was measured: the uncertainty has been growing since then, so the margin
/// at t = 0 is already m_0 + R(age).
struct MarginGrowth {
  double velocity_error = 0.0;  ///< e, m/s, >= 0
  double max_accel = 0.0;       ///< a, m/s^2, >= 0
  /// c, m/s, >= 0: R(s) never exceeds c s. +infinity: no cap.
  double speed_cap = std::numeric_limits<double>::infinity();
  double age = 0.0;             ///< s, >= 0

  /// R is identically 0 (e = a = 0, or c = 0): the margin does not grow.
  bool none() const { return (velocity_error == 0.0 && max_accel == 0.0) || speed_cap == 0.0; }
  /// Every number finite (the cap may be +infinity), non-negative and within Limits.
  bool valid() const;
  /// R(age + t), m: the growth at t seconds after the prediction instant (t >= 0).
  double at(double t) const;
  /// t (s after the prediction instant) from which R is the line c s; +infinity when the cap
  /// never takes over, <= 0 when it already has. R' jumps down there (from e + a s* to c),
  /// so it is a breakpoint of the per-axis times.
  double capTime() const;
  /// The largest growth rate R' over t in [t0, t1], m/s (t0 <= t1).
  double maxRate(double t0, double t1) const;
};

/// R(age + t0 + x) = c0 + c1 x + c2 x^2 on one stretch [t0, t1] that does not straddle
/// capTime(): exact there, and never below R on the whole stretch when it does (either
/// branch of the min() lies above R beyond the crossover).
struct GrowthPiece {
  double c0 = 0.0;  ///< m
  double c1 = 0.0;  ///< m/s
  double c2 = 0.0;  ///< m/s^2
  double at(double x) const { return c0 + x * (c1 + x * c2); }
  bool linear() const { return c2 == 0.0; }
};

/// The polynomial of `growth` on [t0, t1] (the branch of the min() that holds at its middle).
GrowthPiece growthPiece(const MarginGrowth& growth, double t0, double t1);

/// One segment of a piecewise constant-twist motion (ProximityWorld::setPath): from `start`
/// until the next segment's start (the last one: the end of the horizon) the body moves with
/// the constant twist of `motion`, whose pose is the body's pose at `start`:
/// pose(t) = motion.poseAt(t - start). Segments need not join; at a breakpoint the body is
/// where the new segment starts (and, the instant before, where the old one ends).
struct MotionSegment {
  double start = 0.0;   ///< s after the prediction instant; the first segment starts at 0
  BodyMotion motion;    ///< pose at `start`, and the twist held until the next segment
  /// m (>= 0), added to the body's margin during this segment: e.g. a bound on how far the
  /// segment's straight-line motion can leave the true motion it stands for.
  double margin = 0.0;
};

/// A segment as the per-pair stages use it, with its bounds over the horizon.
struct PathSegment {
  double start = 0.0;         ///< s
  double end = 0.0;           ///< s: the next segment's start, or the horizon (clipped to it)
  BodyMotion motion;          ///< pose at `start`, constant twist
  double extra_margin = 0.0;  ///< m: the segment's own margin (MotionSegment::margin)
  double margin = 0.0;        ///< m: the body's margin plus extra_margin
  /// Half extents (m) of an axis-aligned box centred on the moving centre that holds the shape
  /// and `margin` in every orientation over [start, end] (rotationHalfExtents); no growth.
  Eigen::Vector3d half = Eigen::Vector3d::Zero();

  /// Centre at time t (s, within [start, end]).
  Eigen::Vector3d centreAt(double t) const { return motion.position + motion.linear_velocity * (t - start); }
};

/// True when `segments` is a valid path: 1 to Limits::kMaxSegments segments, the first
/// starting at 0, starts finite, strictly increasing and at most Limits::kMaxHorizon, every
/// motion valid(), every margin validMargin().
bool validPath(const MotionSegment* segments, int count);

/// For a path of `count` segments (start, motion and extra_margin set): fills each segment's
/// end (clipped to `horizon`; a segment starting at or after the horizon, other than the first,
/// gets end = start and is not used), margin (`margin` + extra_margin) and half; returns the
/// world box that holds the body at every t in [0, horizon]: the union of every used segment's
/// swept box (its box at its start and at its end), each grown by growth.at(end).
Aabb preparePath(const Shape& shape, double margin, const MarginGrowth& growth, double horizon,
                 PathSegment* segments, int count);

/// Segments of a prepared path that the horizon uses (the first, and those starting before it).
int usedSegments(const PathSegment* segments, int count, double horizon);

}  // namespace workspace_proximity

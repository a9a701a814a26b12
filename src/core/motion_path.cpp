#include "workspace_proximity/motion_path.hpp"

#include <algorithm>
#include <cmath>

#include "workspace_proximity/swept_bounds.hpp"

namespace workspace_proximity {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// s (since the observation) from which R(s) = c s: where e s + a s^2 / 2 reaches c s.
double capOnset(const MarginGrowth& g) {
  if (!(g.speed_cap < kInf)) return kInf;
  if (g.velocity_error >= g.speed_cap) return 0.0;  // the line is below from the start
  if (g.max_accel == 0.0) return kInf;              // e s < c s for ever
  return 2.0 * (g.speed_cap - g.velocity_error) / g.max_accel;
}

bool nonNegative(double x, double hi) { return std::isfinite(x) && x >= 0.0 && x <= hi; }

}  // namespace

bool MarginGrowth::valid() const {
  return nonNegative(velocity_error, Limits::kMaxSpeed) && nonNegative(max_accel, Limits::kMaxAccel) &&
         (speed_cap == kInf || nonNegative(speed_cap, 2.0 * Limits::kMaxSpeed)) &&
         nonNegative(age, Limits::kMaxHorizon);
}

double MarginGrowth::at(double t) const {
  if (none()) return 0.0;
  const double s = age + t;
  const double quadratic = s * (velocity_error + 0.5 * max_accel * s);
  return speed_cap < kInf ? std::min(quadratic, speed_cap * s) : quadratic;
}

double MarginGrowth::capTime() const { return none() ? kInf : capOnset(*this) - age; }

double MarginGrowth::maxRate(double t0, double t1) const {
  if (none()) return 0.0;
  const double onset = capOnset(*this);
  const double s0 = age + t0, s1 = age + t1;
  // R' = e + a s grows until the onset, then drops to c (e + a s* >= c there).
  if (s0 >= onset) return speed_cap;
  return velocity_error + max_accel * std::min(s1, onset);
}

GrowthPiece growthPiece(const MarginGrowth& growth, double t0, double t1) {
  GrowthPiece p;
  if (growth.none()) return p;
  const double s0 = growth.age + t0;
  if (growth.age + 0.5 * (t0 + t1) >= capOnset(growth)) {
    p.c0 = growth.speed_cap * s0;  // c (s0 + x)
    p.c1 = growth.speed_cap;
    return p;
  }
  // e (s0 + x) + a (s0 + x)^2 / 2
  p.c0 = s0 * (growth.velocity_error + 0.5 * growth.max_accel * s0);
  p.c1 = growth.velocity_error + growth.max_accel * s0;
  p.c2 = 0.5 * growth.max_accel;
  return p;
}

bool validPath(const MotionSegment* segments, int count) {
  if (segments == nullptr || count < 1 || count > Limits::kMaxSegments) return false;
  if (segments[0].start != 0.0) return false;
  for (int k = 0; k < count; ++k) {
    const MotionSegment& s = segments[k];
    if (!std::isfinite(s.start) || s.start > Limits::kMaxHorizon) return false;
    if (k > 0 && !(s.start > segments[k - 1].start)) return false;
    if (!s.motion.valid() || !validMargin(s.margin)) return false;
  }
  return true;
}

int usedSegments(const PathSegment* segments, int count, double horizon) {
  int used = 1;
  while (used < count && segments[used].start < horizon) ++used;
  return used;
}

Aabb preparePath(const Shape& shape, double margin, const MarginGrowth& growth, double horizon,
                 PathSegment* segments, int count) {
  const int used = usedSegments(segments, count, horizon);
  Aabb box;
  for (int k = 0; k < count; ++k) {
    PathSegment& s = segments[k];
    s.margin = margin + s.extra_margin;
    if (k >= used) {
      s.end = s.start;  // beyond the horizon: not used
      continue;
    }
    s.end = k + 1 < used ? segments[k + 1].start : std::max(horizon, 0.0);
    const double duration = s.end - s.start;
    s.half = rotationHalfExtents(shape, s.motion, s.margin, duration);
    // The centre moves on a straight line within the segment: the union of the boxes at its
    // two ends holds every box in between; the growth is largest at the end.
    const Eigen::Vector3d half = s.half.array() + growth.at(s.end);
    const Eigen::Vector3d from = s.motion.position;
    const Eigen::Vector3d to = s.motion.position + s.motion.linear_velocity * duration;
    const Aabb swept{from.cwiseMin(to) - half, from.cwiseMax(to) + half};
    box = k == 0 ? swept : box.merged(swept);
  }
  return box;
}

}  // namespace workspace_proximity

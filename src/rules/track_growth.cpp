#include "workspace_proximity/rules/track_growth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace workspace_proximity {
namespace {

// A stamp ahead of the prediction instant (allowed up to ~max_future) is extrapolated
// backwards, which is as uncertain as forwards: R(|age| + t) bounds both.
double growthAge(double age) {
  const double a = std::abs(age);
  return std::isfinite(a) ? std::min(a, Limits::kMaxHorizon) : 0.0;
}

}  // namespace

double unknownVelocitySpeed(const LabelSettings& label) {
  if (label.max_speed > 0.0) return label.max_speed;
  return std::max(label.ssm_min_speed, kUnknownVelocityFallbackSpeed);
}

double trackMargin(const LabelSettings& label, double position_error) {
  // Negative or NaN own errors were refused by checkBox; max() keeps the label as a floor.
  return label.margin + std::max(label.position_error, position_error);
}

MarginGrowth trackGrowth(const LabelSettings& label, double speed, double age,
                         const TrackErrors& own) {
  MarginGrowth g;
  if (!own.velocity_known) {
    // Nominal velocity 0 (the table zeroes it): any motion at most v_u fast stays within
    // v_u s of the measured centre, and min(v_u s + 0 s^2, v_u s) is exactly that line.
    const double v = std::min(unknownVelocitySpeed(label), Limits::kMaxSpeed);
    g.velocity_error = v;
    g.speed_cap = v;
    g.age = growthAge(age);
    return g;
  }
  const double e = std::max(label.velocity_error, own.velocity_error);
  if (e == 0.0 && label.max_accel == 0.0) return g;  // today's prediction
  // The core's limit is far beyond any tracker: clipping there only matters for nonsense.
  g.velocity_error = std::min(e, Limits::kMaxSpeed);
  g.max_accel = label.max_accel;
  // A cap beyond the core's range is no cap: dropping it can only grow the margin.
  const double cap = label.max_speed + speed;
  if (label.max_speed > 0.0 && std::isfinite(cap) && cap <= 2.0 * Limits::kMaxSpeed) {
    g.speed_cap = cap;
  }
  g.age = growthAge(age);
  return g;
}

}  // namespace workspace_proximity

#include "workspace_proximity/rules/track_growth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace workspace_proximity {

double trackMargin(const LabelSettings& label) { return label.margin + label.position_error; }

MarginGrowth trackGrowth(const LabelSettings& label, double speed, double age) {
  MarginGrowth g;
  if (label.velocity_error == 0.0 && label.max_accel == 0.0) return g;  // today's prediction
  g.velocity_error = label.velocity_error;
  g.max_accel = label.max_accel;
  // A cap beyond the core's range is no cap: dropping it can only grow the margin.
  const double cap = label.max_speed + speed;
  if (label.max_speed > 0.0 && std::isfinite(cap) && cap <= 2.0 * Limits::kMaxSpeed) {
    g.speed_cap = cap;
  }
  // A stamp ahead of the prediction instant (allowed up to ~max_future) is extrapolated
  // backwards, which is as uncertain as forwards: R(|age| + t) bounds both.
  const double a = std::abs(age);
  g.age = std::isfinite(a) ? std::min(a, Limits::kMaxHorizon) : 0.0;
  return g;
}

}  // namespace workspace_proximity

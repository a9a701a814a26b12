#include "workspace_proximity/rules/ssm_rule.hpp"

#include <algorithm>

namespace workspace_proximity {

double protectiveSeparation(const SsmParams& p, double v_h, double v_r) {
  return v_h * (p.reaction_time + p.stopping_time) + v_r * p.reaction_time +
         v_r * p.stopping_time / 2.0 + p.intrusion_distance + p.sensor_uncertainty +
         p.robot_uncertainty;
}

double allowedRobotSpeed(const SsmParams& p, double d, double v_h) {
  const double spare = d - v_h * (p.reaction_time + p.stopping_time) - p.intrusion_distance -
                       p.sensor_uncertainty - p.robot_uncertainty;
  const double per_speed = p.reaction_time + p.stopping_time / 2.0;  // m per m/s of robot speed
  if (!(spare > 0.0)) return 0.0;
  // Both times zero: any speed fits once the constant terms do.
  return per_speed > 0.0 ? spare / per_speed : p.robot_max_speed;
}

double pairScale(const SsmParams& p, double d, double v_h) {
  if (!(p.robot_max_speed > 0.0)) return 0.0;
  return std::min(1.0, allowedRobotSpeed(p, d, v_h) / p.robot_max_speed);
}

double SpeedScaleFilter::update(Stamp now, double raw) {
  raw = std::clamp(raw, 0.0, 1.0);
  if (raw <= output_) {
    output_ = raw;  // drops at once
    above_since_ = -1;
  } else {
    if (above_since_ < 0) above_since_ = now;
    const Stamp held = above_since_ + nanoseconds(hold_);
    if (now >= held) {
      // Rises by at most rate per second, counted from the later of the last update and the
      // end of the hold (and never past the raw scale).
      const double dt = std::max(0.0, secondsBetween(std::max(last_, held), now));
      output_ = std::min(raw, output_ + rate_ * dt);
    }
  }
  last_ = now;
  return output_;
}

}  // namespace workspace_proximity

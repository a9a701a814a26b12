#include "workspace_proximity/ros/rejection_log.hpp"

#include <string>

#include <ros/console.h>

namespace workspace_proximity {

void RejectionLog::onRejection(const Rejection& r) {
  if (r.reason == Drop::kSuperseded) return;
  const auto i = static_cast<std::size_t>(r.reason);
  if (i >= kReasons) return;
  const ros::WallTime now = ros::WallTime::now();
  if (!last_[i].isZero() && (now - last_[i]).toSec() < period_) {
    ++suppressed_[i];
    return;
  }
  last_[i] = now;
  const std::string more =
      suppressed_[i] == 0 ? std::string()
                          : " (" + std::to_string(suppressed_[i]) + " more like it not shown)";
  suppressed_[i] = 0;
  const std::string source(r.source);
  if (r.reason == Drop::kArrayFailure || r.reason == Drop::kCycleFailure) {
    ROS_ERROR("proximity_monitor: %s: %s: %s%s", source.c_str(), dropName(r.reason),
              r.detail.c_str(), more.c_str());
  } else if (r.id.empty()) {
    ROS_WARN("proximity_monitor: %s: %s: %s%s", source.c_str(), dropName(r.reason),
             r.detail.c_str(), more.c_str());
  } else {
    const std::string id(r.id);
    ROS_WARN("proximity_monitor: %s: track '%s' dropped (%s): %s%s", source.c_str(), id.c_str(),
             dropName(r.reason), r.detail.c_str(), more.c_str());
  }
}

}  // namespace workspace_proximity

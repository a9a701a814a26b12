// The ROS-free rules layer from a user's package: parameters checked, one cycle, a report.
#include <cstdio>

#include "workspace_proximity/rules/monitor.hpp"
namespace wp = workspace_proximity;

int main() {
  wp::MonitorParams params;
  if (!wp::validate(params).empty()) return 1;
  wp::RobotBodySpec post;
  post.name = "post";
  post.frame = "base";
  post.shape = wp::Shape::box({0.5, 0.5, 0.5});
  wp::Monitor monitor(params, {post}, {"/boxes"}, false, nullptr);
  monitor.poseRobot(0, wp::BodyMotion());
  wp::CycleTiming timing;
  wp::StageClock clock(&timing);
  const wp::CycleReport& report = monitor.cycle(1000000000, &clock);
  // Nothing heard from /boxes yet: DEGRADED, never clear.
  std::printf("use_monitor: %s, %zu events\n", report.degraded ? "DEGRADED" : "OK", report.eventCount());
  return report.degraded ? 0 : 1;
}

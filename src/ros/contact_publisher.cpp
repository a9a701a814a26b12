#include "workspace_proximity/ros/contact_publisher.hpp"

#include <chrono>

#include "workspace_proximity/ros/conversions.hpp"

namespace workspace_proximity {

void fillContacts(const CycleReport& report, const ProximityWorld& world,
                  const std::string& fixed_frame, ContactEventArray* out) {
  out->header.stamp = toTime(report.stamp);
  out->header.frame_id = fixed_frame;
  const std::size_t n = report.eventCount();
  out->events.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const PairEvent& e = report.event(i);
    ContactEvent& msg = out->events[i];
    toMsg(e, world.desc(e.body_a), world.desc(e.body_b), report.levels[i], &msg);
    msg.stale = report.stale[i] != 0;
  }
  out->status = report.degraded ? ContactEventArray::DEGRADED : ContactEventArray::OK;
  out->status_details.assign(report.status_lines.begin(), report.status_lines.end());
}

ContactPublisher::ContactPublisher(ros::NodeHandle& nh, const std::string& fixed_frame)
    : publisher_(nh.advertise<ContactEventArray>("contacts", 10)), fixed_frame_(fixed_frame) {}

double ContactPublisher::publish(const CycleReport& report, const ProximityWorld& world) {
  fillContacts(report, world, fixed_frame_, &msg_);
  const auto start = std::chrono::steady_clock::now();
  publisher_.publish(msg_);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace workspace_proximity

#pragma once
/// The `contacts` topic: one ContactEventArray per cycle, rendered from the cycle's report.

#include <string>

#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <workspace_proximity/ContactEventArray.h>

#include "workspace_proximity/rules/cycle_report.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace workspace_proximity {

/// The report as a message, written into `out` (resized, not cleared: kept elements keep
/// their strings' capacity, so steady cycles rewrite the message in place). Bodies are named
/// from `world` (removed bodies stay nameable until the next predict).
void fillContacts(const CycleReport& report, const ProximityWorld& world,
                  const std::string& fixed_frame, ContactEventArray* out);

class ContactPublisher {
 public:
  ContactPublisher(ros::NodeHandle& nh, const std::string& fixed_frame);
  /// Fills the message and publishes it; returns the time publish() took, ms (serialisation
  /// for the remote subscribers and the hand-off to their connections).
  double publish(const CycleReport& report, const ProximityWorld& world);

 private:
  ros::Publisher publisher_;
  std::string fixed_frame_;
  ContactEventArray msg_;  // reused every cycle
};

}  // namespace workspace_proximity

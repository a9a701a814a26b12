#pragma once
/// The outputs of speed and separation monitoring, rendered from a cycle's verdict:
/// `speed_scale` (std_msgs/Float64), `safety_status` (SafetyStatus) and `speed_override`
/// (std_msgs/Int64, percent) every cycle, and the optional stop actions once per transition
/// into a protective stop: an empty trajectory_msgs/JointTrajectory on each
/// ~ssm/stop_trajectory_topics and "stop" (std_msgs/String) on each ~ssm/stop_event_topics.
/// The stop latch's events (rules/stop_latch.hpp) are logged, and its halt request (stop
/// category 1) goes to ~ssm/halt_topic (std_msgs/Empty) or ~ssm/halt_service (std_srvs/Trigger,
/// called from a thread of its own so that the cycle never waits for it).

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <workspace_proximity/SafetyStatus.h>

#include "workspace_proximity/rules/cycle_report.hpp"
#include "workspace_proximity/rules/ssm_rule.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace workspace_proximity {

/// The verdict as a message (bodies named from `world`, which names them until the next
/// predict). Strings are reassigned in place.
void fillSafetyStatus(const CycleReport& report, const ProximityWorld& world,
                      const std::string& fixed_frame, SafetyStatus* out);

/// round(100 x scale), in [0, 100].
std::int64_t speedOverride(double scale);

class SsmPublisher {
 public:
  /// Advertises the topics in `nh`'s namespace (stop topics resolved there too).
  SsmPublisher(ros::NodeHandle& nh, const std::string& fixed_frame, const SsmParams& params);
  ~SsmPublisher();
  /// One cycle's outputs. Stop actions go out when the scale reaches 0 after having been above
  /// it (or at the first cycle), and again only after it has risen above 0.
  void publish(const CycleReport& report, const ProximityWorld& world);
  /// The configuration's fingerprint on safety_status from the next cycle (config_fingerprint.hpp).
  void setFingerprint(const std::string& fingerprint) { msg_.config_fingerprint = fingerprint; }
  /// Protective stops so far (transitions into a scale of 0).
  std::uint64_t stops() const { return stops_; }
  /// Whether speed_scale, speed_override or safety_status has a subscriber now.
  bool listened() const {
    return scale_pub_.getNumSubscribers() + override_pub_.getNumSubscribers() +
               status_pub_.getNumSubscribers() >
           0;
  }

 private:
  void stopActions(const CycleReport& report);
  void latchEvents(const CycleReport& report);
  void haltLoop();

  std::string fixed_frame_;
  ros::Publisher scale_pub_;
  ros::Publisher status_pub_;
  ros::Publisher override_pub_;
  std::vector<ros::Publisher> trajectory_pubs_;
  std::vector<ros::Publisher> event_pubs_;
  ros::Publisher halt_pub_;       // ~ssm/halt_topic, when set
  ros::NodeHandle nh_;
  std::string halt_service_;      // ~ssm/halt_service resolved, when set
  std::thread halt_thread_;       // calls the halt service
  std::mutex halt_mutex_;
  std::condition_variable halt_wake_;
  int halts_waiting_ = 0;         // halt requests not yet called
  bool closing_ = false;
  SafetyStatus msg_;       // reused every cycle
  bool stopped_ = false;   // the scale is 0 and the stop actions went out
  std::uint64_t stops_ = 0;
};

}  // namespace workspace_proximity

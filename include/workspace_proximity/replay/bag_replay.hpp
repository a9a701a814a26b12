#pragma once
/// The offline replay: a recorded bag through the node's own pipeline (MonitorBridges) and its
/// cycle runner, with simulated time taken from the bag. It drives the pipeline exactly as the
/// node does:
///   - each tracker array is handed to onArray at the time the recorder received it;
///   - each /tf and /tf_static message is inserted into a tf2::BufferCore at its receive time
///     (/tf_static as static transforms), as tf2_ros's listener inserts them;
///   - a cycle runs every 1 / ~rate seconds of bag time, from the bag's first message (the
///     first cycle one period after it); a message received exactly at a cycle's instant is
///     delivered before that cycle;
///   - with ~cycle_trigger: input, a cycle runs instead at the receive time of an array of
///     ~trigger_source when CycleTrigger's token bucket allows (at most ~rate a second), and a
///     floor cycle one period after the last cycle when none did (the node's one-shot timer);
///   - each cycle's report is rendered with fillContacts, as the node publishes it;
///   - a stretch of more than kSkipGap seconds without any message (bags merged from two
///     sessions, or one message with a wrong time) is not cycled through: cycles run until
///     every input has timed out (the monitor's state no longer changes but for the stamps),
///     then resume shortly before the next message; the skipped stretches are reported.
/// The node's time is the bag's: while the replay runs, ros::Time::now() is set to the bag
/// time (so rosconsole's throttled warnings count bag seconds).

#include <chrono>
#include <memory>
#include <cstdint>
#include <string>
#include <unordered_set>
#include <vector>

#include <tf2/buffer_core.h>
#include <workspace_proximity/ContactEventArray.h>

#include "workspace_proximity/rules/cycle_runner.hpp"
#include "workspace_proximity/rules/cycle_trigger.hpp"
#include "workspace_proximity/rules/monitor.hpp"
#include "workspace_proximity/replay/bag_input.hpp"
#include "workspace_proximity/ros/monitor_bridges.hpp"
#include "workspace_proximity/ros/rejection_log.hpp"

namespace workspace_proximity {

/// What the replay runs: the node's configuration, already read and validated.
struct ReplaySetup {
  MonitorParams params;                 ///< passed validate()
  std::vector<RobotBodySpec> robot;     ///< robotBodiesFromFile
  std::vector<std::string> topics;      ///< resolved input topics ("/tracked_objects")
  bool qualify = false;                 ///< ids prefixed by their topic (several inputs)
  /// Problems lasting the whole run (Monitor::addPermanentIssue), e.g. a robot link the URDF
  /// model cannot represent: every cycle is DEGRADED with these lines, as in the node.
  std::vector<std::string> permanent_issues;
  /// The URDF's text ("" = none): with ~use_joint_states the robot links its joints move are
  /// posed from the bag's joint_states (and ~trajectory_topic), as in the node.
  std::string urdf_xml;
};

/// Told of every cycle, in order.
class ReplaySink {
 public:
  virtual ~ReplaySink() = default;
  /// `contacts` is the cycle's ContactEventArray as the node would publish it.
  virtual void onCycle(const CycleReport& report, const ContactEventArray& contacts,
                       const Monitor& monitor) = 0;
};

/// A stretch of bag time without input whose cycles were skipped.
struct SkippedGap {
  Stamp from = 0;  ///< first cycle instant not run
  Stamp to = 0;    ///< first cycle instant run again
  std::uint64_t cycles = 0;
};

/// What a whole replay saw and did.
struct ReplayStats {
  Stamp begin = 0;  ///< the bag's first and last receive time, ns
  Stamp end = 0;
  std::uint64_t cycles = 0;
  std::uint64_t degraded_cycles = 0;
  std::uint64_t tf_messages = 0;
  std::uint64_t tf_static_messages = 0;
  std::uint64_t arrays = 0;
  std::uint64_t events_begin = 0;
  std::uint64_t events_ongoing = 0;
  std::uint64_t events_end = 0;
  std::uint64_t distinct_tracks = 0;  ///< distinct track ids seen at a cycle
  int max_tracks = 0;                 ///< most tracks at one cycle
  std::uint64_t resets = 0;           ///< clock went back (a bag looping on itself)
  DropCounters drops;
  double wall_seconds = 0.0;          ///< time the replay took (reading included)
  /// One line per frame the prediction needed but the bag's tf never gave (a robot body's
  /// frame, or a tracker array's frame); non-empty means the replay is incomplete.
  std::vector<std::string> missing_frames;
  std::vector<SkippedGap> gaps;  ///< stretches without input whose cycles were skipped

  double bagSeconds() const { return secondsBetween(begin, end); }
};

class BagReplay : private BagVisitor, private CycleOutput {
 public:
  /// s without any message after which cycles are skipped (see above).
  static constexpr double kSkipGap = 60.0;

  explicit BagReplay(const ReplaySetup& setup);

  /// Replays `bag` from its first to its last message. `rate_factor` > 0 paces the replay at
  /// that many times real time; 0 runs as fast as possible (the results are the same: every
  /// time the monitor sees is bag time). Throws ReplayError (kBag) for a bag without any tf
  /// when there are robot bodies, or a bag damaged midway.
  ReplayStats run(BagInput* bag, ReplaySink* sink, double rate_factor);

  const Monitor& monitor() const { return bridges_.monitor(); }

 private:
  void onTf(const tf2_msgs::TFMessage& msg, bool is_static, Stamp received) override;
  void onArray(int source, const TrackedBoxArray::ConstPtr& msg, Stamp received) override;
  void onForeign(int source, const BagTopic& topic, const std::uint8_t* bytes, std::size_t size,
                 Stamp received) override;
  void onJointState(const sensor_msgs::JointState& msg, Stamp received) override;
  void onTrajectory(const trajectory_msgs::JointTrajectory& msg, Stamp received) override;
  void onPerceptionStatus(int index, const PerceptionStatus& msg, Stamp received) override;
  void onInput(Stamp received);  // cycles due before it, the clock, the last input
  void cyclesBefore(Stamp t);  // every cycle due before t (skipping a long stretch without input)
  void runCycle(Stamp now);
  // CycleOutput: the contacts as the node would publish them.
  void contacts(const CycleReport& report, const ProximityWorld& world) override;
  void advanceClock(Stamp t);  // ROS time and pacing
  void checkFrames();

  ReplaySetup setup_;
  tf2::BufferCore tf_;
  RejectionLog rejection_log_;
  MonitorBridges bridges_;
  std::shared_ptr<const KinematicModel> joint_model_;  // set when links are posed from joints
  ContactEventArray contacts_;  // reused every cycle
  ReplaySink* sink_ = nullptr;
  ReplayStats stats_;
  Stamp period_ = 0;
  Stamp next_cycle_ = 0;   // the next timer cycle (input trigger: the floor)
  bool input_trigger_ = false;
  int trigger_source_ = 0;  // index of the trigger topic
  CycleTrigger trigger_;
  double rate_factor_ = 0.0;
  std::chrono::steady_clock::time_point wall_start_;
  Stamp last_input_ = 0;  // receive time of the last message
  Stamp settle_ = 0;      // after this long without input nothing changes but the stamps
  Stamp skipped_ = 0;     // bag time skipped so far (not paced)

  // Frames: those tf gave (parents and children), those the arrays came in, bodies ever posed.
  std::unordered_set<std::string> tf_frames_;
  std::vector<std::string> array_frames_;  // distinct, in order of appearance
  std::vector<std::uint8_t> robot_posed_;
  std::unordered_set<std::string> track_keys_;
};

}  // namespace workspace_proximity

#include "workspace_proximity/replay/bag_replay.hpp"

#include <algorithm>
#include <thread>

#include <ros/console.h>
#include <ros/time.h>

#include "workspace_proximity/ros/contact_publisher.hpp"
#include "workspace_proximity/ros/conversions.hpp"
#include "workspace_proximity/replay/replay_options.hpp"

namespace workspace_proximity {

BagReplay::BagReplay(const ReplaySetup& setup)
    : setup_(setup),
      tf_(MonitorBridges::tfCacheTime(setup.params)),
      bridges_(setup_.params, setup_.robot, setup_.topics, setup_.qualify, &tf_, &rejection_log_),
      period_(nanoseconds(1.0 / setup.params.rate)),
      input_trigger_(setup.params.cycle_trigger == "input"),
      trigger_(setup.params.rate),
      // Every timeout of the monitor has run out: tracks dropped (their pairs ended), sources
      // silent, robot links stale; a second more for good measure.
      settle_(nanoseconds(std::max({setup.params.track_timeout, setup.params.source_timeout,
                                    setup.params.tf_timeout, setup.params.stale_after,
                                    setup.params.velocity_window}) + 1.0)),
      robot_posed_(setup.robot.size(), 0) {
  for (const std::string& line : setup_.permanent_issues) bridges_.addPermanentIssue(line);
  // As the node does (ProximityMonitor::enableJoints): links moved by joints from joint_states.
  joint_model_ = MonitorBridges::jointModel(setup_.params, setup_.urdf_xml);
  if (!setup_.params.trigger_source.empty()) {
    const std::string wanted = resolveTopic(setup_.params.trigger_source);
    for (std::size_t i = 0; i < setup_.topics.size(); ++i) {
      if (setup_.topics[i] == wanted) trigger_source_ = static_cast<int>(i);
    }
  }
}

ReplayStats BagReplay::run(BagInput* bag, ReplaySink* sink, double rate_factor) {
  sink_ = sink;
  rate_factor_ = rate_factor;
  stats_ = ReplayStats();
  stats_.begin = bag->begin();
  stats_.end = bag->end();

  bool has_tf = false;
  for (const BagTopic& t : bag->topics()) {
    if ((t.kind == BagTopicKind::kTf || t.kind == BagTopicKind::kTfStatic) && t.messages > 0) {
      has_tf = true;
    }
  }
  if (!has_tf && !setup_.robot.empty()) {
    std::string frames;
    for (const RobotBodySpec& b : setup_.robot) {
      if (frames.find("'" + b.frame + "'") != std::string::npos) continue;
      frames += (frames.empty() ? "'" : ", '") + b.frame + "'";
    }
    throw ReplayError(ReplayError::kBag,
                      "bag " + bag->path() + ": has no /tf or /tf_static, so the robot's frames (" +
                          frames + ") can never be posed");
  }

  // Simulated time: ROS time follows the bag from here on.
  ros::Time::init();
  ros::Time::setNow(toTime(stats_.begin));
  wall_start_ = std::chrono::steady_clock::now();
  next_cycle_ = stats_.begin + period_;
  last_input_ = stats_.begin;
  skipped_ = 0;

  if (joint_model_ && !bridges_.jointsEnabled()) {
    // The links joints move are posed from the bag's joint states, as the node poses them;
    // a bag recorded without them (tf only) keeps every link on the tf it recorded.
    const std::string joint_topic = resolveTopic("joint_states");
    bool recorded = false;
    for (const BagTopic& t : bag->topics()) {
      recorded = recorded || (t.name == joint_topic && t.kind == BagTopicKind::kJointState && t.messages > 0);
    }
    if (recorded) {
      bridges_.enableJoints(joint_model_);
      const std::string& traj = setup_.params.trajectory_topic;
      for (const std::string& w : bag->replayJoints(joint_topic, traj.empty() ? std::string() : resolveTopic(traj))) {
        ROS_WARN("replay: %s", w.c_str());
      }
    } else {
      ROS_WARN("replay: the bag has no %s: every robot link from the recorded tf", joint_topic.c_str());
    }
  }
  // The perception front ends' statuses as recorded (a topic missing: DEGRADED, as live).
  std::vector<std::string> perception;
  for (const std::string& t : setup_.params.perception_status_topics) perception.push_back(resolveTopic(t));
  for (const std::string& w : bag->replayPerception(perception)) ROS_WARN("replay: %s", w.c_str());
  bag->stream(this);
  // Cycles up to the last message, inclusive.
  while (next_cycle_ <= stats_.end) {
    if (input_trigger_) trigger_.onFloor(next_cycle_);
    runCycle(next_cycle_);
    next_cycle_ += period_;
  }

  stats_.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
  stats_.drops = monitor().drops();
  stats_.resets = monitor().status().resets;
  stats_.distinct_tracks = track_keys_.size();
  checkFrames();
  return stats_;
}

void BagReplay::onTf(const tf2_msgs::TFMessage& msg, bool is_static, Stamp received) {
  cyclesBefore(received);
  advanceClock(received);
  last_input_ = received;
  ++(is_static ? stats_.tf_static_messages : stats_.tf_messages);
  for (const geometry_msgs::TransformStamped& t : msg.transforms) {
    // Invalid transforms (empty or equal frames, NaN) are refused by tf2 with its own error,
    // as in the node.
    tf_.setTransform(t, "bag", is_static);
    tf_frames_.insert(t.header.frame_id);
    tf_frames_.insert(t.child_frame_id);
  }
}

void BagReplay::onInput(Stamp received) {
  cyclesBefore(received);
  advanceClock(received);
  last_input_ = received;
}

void BagReplay::onJointState(const sensor_msgs::JointState& msg, Stamp received) {
  onInput(received);
  bridges_.onJointState(msg, received);
}

void BagReplay::onPerceptionStatus(int index, const PerceptionStatus& msg, Stamp received) {
  onInput(received);
  bridges_.onPerceptionStatus(index, received, msg.degraded, msg.reasons, msg.unseen_share);
}

void BagReplay::onTrajectory(const trajectory_msgs::JointTrajectory& msg, Stamp received) {
  onInput(received);
  bridges_.onTrajectory(msg, received);
}

void BagReplay::onArray(int source, const TrackedBoxArray::ConstPtr& msg, Stamp received) {
  cyclesBefore(received);
  advanceClock(received);
  last_input_ = received;
  ++stats_.arrays;
  const std::string& frame = msg->header.frame_id;
  if (std::find(array_frames_.begin(), array_frames_.end(), frame) == array_frames_.end()) {
    array_frames_.push_back(frame);
  }
  bridges_.onArray(source, msg, received);
  // ~cycle_trigger: input: a cycle at the array's arrival when the bucket allows, and the
  // floor one period after it.
  if (input_trigger_ && source == trigger_source_ && trigger_.onArray(received)) {
    runCycle(received);
    next_cycle_ = trigger_.floorAfter(received);
  }
}

void BagReplay::onForeign(int source, const BagTopic& topic, const std::uint8_t* bytes,
                          std::size_t size, Stamp received) {
  cyclesBefore(received);
  advanceClock(received);
  last_input_ = received;
  ++stats_.arrays;
  if (size > 0) std::copy(bytes, bytes + size, bridges_.foreignBytes(source, size));
  else bridges_.foreignBytes(source, 0);
  bridges_.onForeign(source, topic.type, topic.md5, topic.definition, received);
  // Its frame must be on tf, as an array's (checkFrames).
  const std::string_view frame = bridges_.foreignFrame(source);
  if (!frame.empty() &&
      std::find(array_frames_.begin(), array_frames_.end(), frame) == array_frames_.end()) {
    array_frames_.emplace_back(frame);
  }
  if (input_trigger_ && source == trigger_source_ && trigger_.onArray(received)) {
    runCycle(received);
    next_cycle_ = trigger_.floorAfter(received);
  }
}

void BagReplay::cyclesBefore(Stamp t) {
  const bool long_gap = t - last_input_ > nanoseconds(kSkipGap);
  while (next_cycle_ < t) {
    if (long_gap && next_cycle_ > last_input_ + settle_) {
      // Nothing changes until the next message but the stamps: resume a cycle or two before it,
      // on the same grid.
      const Stamp resume = next_cycle_ + ((t - next_cycle_) / period_ - 1) * period_;
      if (resume > next_cycle_) {
        stats_.gaps.push_back({next_cycle_, resume, static_cast<std::uint64_t>((resume - next_cycle_) / period_)});
        skipped_ += resume - next_cycle_;
        next_cycle_ = resume;
      }
    }
    if (input_trigger_) trigger_.onFloor(next_cycle_);
    runCycle(next_cycle_);
    next_cycle_ += period_;
  }
}

void BagReplay::advanceClock(Stamp t) {
  ros::Time::setNow(toTime(t));
  if (rate_factor_ <= 0.0) return;
  const auto due = wall_start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(
                                         secondsBetween(stats_.begin + skipped_, t) / rate_factor_));
  std::this_thread::sleep_until(due);
}

void BagReplay::contacts(const CycleReport& report, const ProximityWorld& world) {
  fillContacts(report, world, setup_.params.fixed_frame, &contacts_);
}

void BagReplay::runCycle(Stamp now) {
  advanceClock(now);
  // The node's cycle: reset, failure and timing are the runner's; the contacts are contacts().
  bridges_.run(now, this);
  const Monitor& monitor = bridges_.monitor();
  const CycleReport& report = monitor.report();
  ++stats_.cycles;
  if (report.degraded) ++stats_.degraded_cycles;
  for (const ContactEvent& e : contacts_.events) {
    if (e.state == ContactEvent::BEGIN) ++stats_.events_begin;
    else if (e.state == ContactEvent::ONGOING) ++stats_.events_ongoing;
    else ++stats_.events_end;
  }
  const TrackTable& tracks = monitor.tracks();
  stats_.max_tracks = std::max(stats_.max_tracks, tracks.size());
  for (int i = 0; i < tracks.size(); ++i) {
    const std::string& key = tracks.track(i).key;
    if (track_keys_.count(key) == 0) track_keys_.insert(key);
  }
  const RobotBodies& robot = monitor.robot();
  for (int i = 0; i < robot.size(); ++i) {
    if (robot.present(i) && !robot.stale(i)) robot_posed_[static_cast<std::size_t>(i)] = 1;
  }
  if (sink_ != nullptr) sink_->onCycle(report, contacts_, monitor);
}

void BagReplay::checkFrames() {
  const std::string& fixed = setup_.params.fixed_frame;
  auto known = [&](const std::string& frame) { return frame == fixed || tf_frames_.count(frame) > 0; };
  for (std::size_t i = 0; i < setup_.robot.size(); ++i) {
    const RobotBodySpec& b = setup_.robot[i];
    if (!known(b.frame)) {
      stats_.missing_frames.push_back("no tf for frame '" + b.frame + "' (robot body '" + b.name +
                                      "') anywhere in the bag: the body was never posed");
    } else if (robot_posed_[i] == 0) {
      stats_.missing_frames.push_back("robot body '" + b.name + "' was never posed: tf in the bag "
                                      "never connected its frame '" + b.frame + "' to '" + fixed +
                                      "' in time");
    }
  }
  for (const std::string& frame : array_frames_) {
    if (frame.empty()) continue;  // dropped and counted by the monitor (kFrame)
    if (!known(frame)) {
      stats_.missing_frames.push_back("no tf for frame '" + frame + "' (the tracked boxes' frame) "
                                      "anywhere in the bag: its arrays were dropped");
    }
  }
}

}  // namespace workspace_proximity

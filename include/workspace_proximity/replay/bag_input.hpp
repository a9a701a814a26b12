#pragma once
/// A recorded bag as the replay's input: checked when opened (a ROS bag, indexed, complete,
/// the input topics present with the type and definition this build knows), then streamed in
/// the order the recorder received the messages, one message at a time (memory does not grow
/// with the bag's length).
///
/// Replayed topics: /tf, /tf_static and the input topics (TrackedBoxArray, or a foreign
/// tracker type of a known version: foreign_types.hpp); and, when the
/// replay poses the robot from its joints (replayJoints), the joint states and the planned
/// trajectories topic; and the perception front ends' status topics (replayPerception).

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <rosbag/bag.h>
#include <sensor_msgs/JointState.h>
#include <trajectory_msgs/JointTrajectory.h>
#include <tf2_msgs/TFMessage.h>
#include <workspace_proximity/PerceptionStatus.h>
#include <workspace_proximity/TrackedBoxArray.h>

#include "workspace_proximity/rules/stamp.hpp"

namespace workspace_proximity {

/// A problem that stops the replay, with the exit status the tool returns for it.
class ReplayError : public std::runtime_error {
 public:
  /// Exit statuses of replay_bag.
  static constexpr int kUsage = 2;       ///< bad command line
  static constexpr int kConfig = 3;      ///< configuration or URDF unusable
  static constexpr int kBag = 4;         ///< bag unreadable, unindexed, truncated, topic missing
  static constexpr int kIncomplete = 5;  ///< replayed, but a needed frame had no tf in the bag
  static constexpr int kOutput = 6;      ///< cannot write the output folder

  ReplayError(int exit_code, const std::string& what)
      : std::runtime_error(what), exit_code_(exit_code) {}
  int exitCode() const { return exit_code_; }

 private:
  int exit_code_;
};

/// What a topic of the bag is to the replay.
enum class BagTopicKind : std::uint8_t {
  kTf,          ///< /tf: tf2_msgs/TFMessage
  kTfStatic,    ///< /tf_static: tf2_msgs/TFMessage, inserted as static transforms
  kArray,       ///< an input topic: workspace_proximity/TrackedBoxArray
  kForeign,     ///< an input topic of a foreign tracker type (a version foreign_types.hpp knows)
  kJointState,  ///< sensor_msgs/JointState: replayed when replayJoints() names it
  kTrajectory,  ///< trajectory_msgs/JointTrajectory: replayed when replayJoints() names it
  kPerceptionStatus,  ///< workspace_proximity/PerceptionStatus: when replayPerception() names it
  kOther,       ///< not used by the monitor
};

struct BagTopic {
  std::string name;
  std::string type;
  std::uint64_t messages = 0;
  BagTopicKind kind = BagTopicKind::kOther;
  int source = -1;  ///< kArray, kForeign: index of the input topic
  std::string md5;         ///< as recorded
  std::string definition;  ///< the publisher's full message definition, as recorded
};

/// Receives the replayed messages in order. The references are valid during the call only.
class BagVisitor {
 public:
  virtual ~BagVisitor() = default;
  virtual void onTf(const tf2_msgs::TFMessage& msg, bool is_static, Stamp received) = 0;
  virtual void onArray(int source, const TrackedBoxArray::ConstPtr& msg, Stamp received) = 0;
  /// A foreign tracker message of input `source`: its serialized bytes and its topic (type,
  /// md5, definition).
  virtual void onForeign(int source, const BagTopic& topic, const std::uint8_t* bytes,
                         std::size_t size, Stamp received) = 0;
  virtual void onJointState(const sensor_msgs::JointState& msg, Stamp received) {}
  virtual void onTrajectory(const trajectory_msgs::JointTrajectory& msg, Stamp received) {}
  /// A perception front end's status on ~perception_status_topics[index].
  virtual void onPerceptionStatus(int index, const PerceptionStatus& msg, Stamp received) {}
};

class BagInput {
 public:
  /// Opens `path` and checks it; `input_topics` are resolved names ("/tracked_objects").
  /// Throws ReplayError (kBag) naming the problem: no such file, not a ROS bag, not indexed
  /// (an interrupted recording: `rosbag reindex`), truncated or damaged (checkBagStructure,
  /// before rosbag reads it), an input topic missing or of another type or definition (a
  /// foreign type's unknown md5 names its layout difference, as the node does).
  BagInput(const std::string& path, const std::vector<std::string>& input_topics);
  ~BagInput();
  BagInput(const BagInput&) = delete;
  BagInput& operator=(const BagInput&) = delete;

  const std::string& path() const { return path_; }
  /// Receive times of the first and last message (any topic), ns.
  Stamp begin() const { return begin_; }
  Stamp end() const { return end_; }
  /// Every topic of the bag, sorted by name.
  const std::vector<BagTopic>& topics() const { return topics_; }
  /// Messages the replay will read (tf, tf_static, input topics).
  std::uint64_t replayedMessages() const { return replayed_messages_; }

  /// Also replays `joint_topic` (sensor_msgs/JointState) and `trajectory_topic`
  /// (trajectory_msgs/JointTrajectory; "" = none), resolved names, when the bag has them with
  /// those types. Returns the lines to warn about (a topic missing or of another type).
  std::vector<std::string> replayJoints(const std::string& joint_topic,
                                        const std::string& trajectory_topic);
  /// Also replays the perception front ends' status topics (resolved names, in
  /// ~perception_status_topics' order) the bag has as workspace_proximity/PerceptionStatus.
  /// Returns the lines to warn about (a topic missing: the replay is DEGRADED for it).
  std::vector<std::string> replayPerception(const std::vector<std::string>& topics);

  /// Streams the replayed topics to `visitor` in receive-time order. Throws ReplayError (kBag)
  /// when the bag turns out damaged midway (the messages before it were delivered).
  void stream(BagVisitor* visitor);

 private:
  std::string path_;
  rosbag::Bag bag_;
  std::vector<BagTopic> topics_;
  std::vector<std::string> replayed_;  // topic names the view reads
  Stamp begin_ = 0;
  Stamp end_ = 0;
  std::uint64_t replayed_messages_ = 0;
  std::uint32_t min_box_bytes_;        // serialised size of an empty TrackedBox
  std::uint32_t min_transform_bytes_;  // ... of an empty TransformStamped

  // Reused for every message: the serialised bytes and the decoded tf message, and a small
  // pool of arrays per source recycled once the monitor has let go of them.
  std::vector<std::uint8_t> buffer_;
  PerceptionStatus perception_;
  tf2_msgs::TFMessage tf_;
  sensor_msgs::JointState joint_state_;
  trajectory_msgs::JointTrajectory trajectory_;
  std::vector<std::vector<boost::shared_ptr<TrackedBoxArray>>> array_pool_;
};

}  // namespace workspace_proximity

#include "workspace_proximity/replay/bag_input.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <sstream>

#include <ros/serialization.h>
#include <rosbag/exceptions.h>
#include <rosbag/query.h>
#include <rosbag/view.h>

#include "workspace_proximity/replay/bag_check.hpp"
#include "workspace_proximity/rules/foreign_types.hpp"
#include "workspace_proximity/ros/conversions.hpp"

namespace workspace_proximity {
namespace {

constexpr char kArrayType[] = "workspace_proximity/TrackedBoxArray";

ReplayError bagError(const std::string& path, const std::string& what) {
  return ReplayError(ReplayError::kBag, "bag " + path + ": " + what);
}

BagTopicKind kindOf(const std::string& topic, const std::string& type,
                    const std::vector<std::string>& inputs, int* source) {
  *source = -1;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (topic == inputs[i]) {
      *source = static_cast<int>(i);
      return BagTopicKind::kArray;
    }
  }
  if (topic == "/tf") return BagTopicKind::kTf;
  if (topic == "/tf_static") return BagTopicKind::kTfStatic;
  if (type == "sensor_msgs/JointState") return BagTopicKind::kJointState;
  if (type == "trajectory_msgs/JointTrajectory") return BagTopicKind::kTrajectory;
  return BagTopicKind::kOther;
}

// The count of the message's top-level list (TFMessage.transforms, TrackedBoxArray.boxes) must
// fit in the bytes that follow it. ROS's deserialiser resizes a list to its count before
// reading any element, so a damaged count would allocate and construct up to 4 billion
// elements; the elements themselves hold no lists, and their strings are checked against the
// bytes left before they are allocated.
bool plausibleCount(const std::vector<std::uint8_t>& bytes, std::size_t count_at, std::uint32_t min_element,
                    std::string* why) {
  if (count_at > bytes.size() || bytes.size() - count_at < 4) {
    *why = "a message is shorter than its own header";
    return false;
  }
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + count_at, 4);
  const std::uint64_t left = bytes.size() - count_at - 4;
  if (std::uint64_t{count} * min_element <= left) return true;
  *why = "a message claims " + std::to_string(count) + " elements in " + std::to_string(left) + " bytes";
  return false;
}

// Where TrackedBoxArray's box count is: after the header (seq, stamp, frame_id).
std::size_t boxCountOffset(const std::vector<std::uint8_t>& bytes) {
  if (bytes.size() < 16) return bytes.size();
  std::uint32_t frame_len = 0;
  std::memcpy(&frame_len, bytes.data() + 12, 4);
  return std::uint64_t{frame_len} > bytes.size() - 16 ? bytes.size() : 16 + std::size_t{frame_len};
}

std::string topicList(const std::vector<BagTopic>& topics) {
  if (topics.empty()) return "none";
  std::string s;
  for (const BagTopic& t : topics) {
    if (!s.empty()) s += ", ";
    s += t.name + " (" + t.type + ")";
  }
  return s;
}

}  // namespace

BagInput::BagInput(const std::string& path, const std::vector<std::string>& input_topics)
    : path_(path),
      min_box_bytes_(ros::serialization::serializationLength(TrackedBox())),
      min_transform_bytes_(ros::serialization::serializationLength(geometry_msgs::TransformStamped())),
      array_pool_(input_topics.size()) {
  // rosbag trusts the file's lengths and offsets: check them first (bag_check.hpp).
  checkBagStructure(path);
  try {
    bag_.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagUnindexedException&) {
    throw bagError(path, "not indexed (interrupted recording); `rosbag reindex " + path +
                             "` rebuilds the index");
  } catch (const std::exception& e) {  // rosbag's exceptions, and bad_alloc on damaged sizes
    throw bagError(path, std::string("cannot be read: ") + e.what() + " (truncated or damaged?)");
  }

  try {
    rosbag::View all(bag_);
    if (all.size() == 0) throw bagError(path, "has no messages");
    begin_ = toStamp(all.getBeginTime());
    end_ = toStamp(all.getEndTime());
    // One entry per topic (a topic may have several connections: one per publisher).
    std::map<std::string, BagTopic> by_name;
    std::map<std::string, std::string> md5_of;
    for (const rosbag::ConnectionInfo* c : all.getConnections()) {
      BagTopic& t = by_name[c->topic];
      if (!t.type.empty() && t.type != c->datatype) {
        throw bagError(path, "topic " + c->topic + " was recorded with two types, " + t.type +
                                 " and " + c->datatype);
      }
      t.name = c->topic;
      t.type = c->datatype;
      t.md5 = c->md5sum;
      t.definition = c->msg_def;
      md5_of[c->topic] = c->md5sum;
    }
    for (auto& kv : by_name) {
      BagTopic& t = kv.second;
      t.kind = kindOf(t.name, t.type, input_topics, &t.source);
      t.messages = rosbag::View(bag_, rosbag::TopicQuery(t.name)).size();
      topics_.push_back(t);
    }

    for (const std::string& input : input_topics) {
      auto it = by_name.find(input);
      if (it == by_name.end()) {
        throw bagError(path, "has no topic " + input +
                                 " (the input topic: ~input_topics in the configuration, or "
                                 "--input-topic); its topics: " + topicList(topics_));
      }
      BagTopic& t = it->second;
      const std::string expected = ros::message_traits::MD5Sum<TrackedBoxArray>::value();
      // This build's TrackedBoxArray is read typed; any other md5 of it (v1, recorded before
      // the per-box errors) is in the foreign catalogue and decoded as the live node does.
      if (isKnownForeignType(t.type) && !(t.type == kArrayType && t.md5 == expected)) {
        // A tracker's own type: read only in a version the decoder knows, never guessed.
        if (findForeignVersion(t.type, t.md5) == nullptr) {
          throw bagError(path, "topic " + input + ": " +
                                   describeUnknownMd5(t.type, t.md5, t.definition));
        }
        for (BagTopic& listed : topics_) {
          if (listed.name == input) listed.kind = BagTopicKind::kForeign;
        }
        continue;
      }
      if (t.type != kArrayType) {
        throw bagError(path, "topic " + input + " has type " + t.type + ", not " + kArrayType +
                                 " nor a tracker type this build reads (" +
                                 describeUnknownType(t.type) + ")");
      }
      // Here the type is TrackedBoxArray with this build's md5 (another md5 of it went to the
      // catalogue above: read when known, refused by name when not).
    }
    for (const BagTopic& t : topics_) {
      if (t.kind != BagTopicKind::kTf && t.kind != BagTopicKind::kTfStatic) continue;
      const std::string expected = ros::message_traits::MD5Sum<tf2_msgs::TFMessage>::value();
      if (md5_of[t.name] != expected) {
        throw bagError(path, "topic " + t.name + " has type " + t.type + ", not tf2_msgs/TFMessage");
      }
    }
    for (const BagTopic& t : topics_) {
      if (t.kind == BagTopicKind::kTf || t.kind == BagTopicKind::kTfStatic ||
          t.kind == BagTopicKind::kArray || t.kind == BagTopicKind::kForeign) {
        replayed_.push_back(t.name);
        replayed_messages_ += t.messages;
      }
    }
  } catch (const ReplayError&) {
    throw;
  } catch (const std::exception& e) {
    throw bagError(path, std::string("cannot be read: ") + e.what());
  }
}

std::vector<std::string> BagInput::replayJoints(const std::string& joint_topic,
                                               const std::string& trajectory_topic) {
  std::vector<std::string> warnings;
  auto add = [&](const std::string& name, BagTopicKind kind, const std::string& type) {
    if (name.empty()) return;
    for (BagTopic& t : topics_) {
      if (t.name != name) continue;
      if (t.kind != kind) {
        warnings.push_back("topic " + name + " has type " + t.type + ", not " + type + "; not replayed");
        return;
      }
      if (std::find(replayed_.begin(), replayed_.end(), name) == replayed_.end()) {
        replayed_.push_back(name);
        replayed_messages_ += t.messages;
      }
      return;
    }
    warnings.push_back("the bag has no " + name + " (" + type + ")");
  };
  add(joint_topic, BagTopicKind::kJointState, "sensor_msgs/JointState");
  add(trajectory_topic, BagTopicKind::kTrajectory, "trajectory_msgs/JointTrajectory");
  return warnings;
}

BagInput::~BagInput() {
  try {
    bag_.close();
  } catch (...) {
    // Closing a bag opened for reading writes nothing; nothing to report.
  }
}

void BagInput::stream(BagVisitor* visitor) {
  // The kind of each replayed topic, looked up by name (a handful of topics).
  std::vector<const BagTopic*> replayed;
  for (const BagTopic& t : topics_) {
    if (std::find(replayed_.begin(), replayed_.end(), t.name) != replayed_.end()) replayed.push_back(&t);
  }
  std::unique_ptr<rosbag::View> view;
  rosbag::View::iterator it;
  Stamp last = begin_;
  auto damaged = [&](const std::string& what) {
    std::ostringstream s;
    s << "damaged " << secondsBetween(begin_, last) << " s after its start: " << what;
    return bagError(path_, s.str());
  };
  try {
    view = std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(replayed_));
    it = view->begin();
  } catch (const std::exception& e) {
    throw damaged(e.what());
  }

  while (true) {
    const BagTopic* topic = nullptr;
    TrackedBoxArray::ConstPtr array;
    try {
      if (it == view->end()) break;
      const rosbag::MessageInstance& m = *it;
      last = toStamp(m.getTime());
      for (const BagTopic* t : replayed) {
        if (t->name == m.getTopic()) topic = t;
      }
      // The message's bytes into the reused buffer, decoded into a reused message: the
      // vectors and strings of the last message keep their capacity.
      const std::uint32_t size = m.size();
      buffer_.resize(size);
      ros::serialization::OStream out(buffer_.data(), size);
      m.write(out);
      ros::serialization::IStream in(buffer_.data(), size);
      std::string why;
      const bool joints = topic->kind == BagTopicKind::kJointState || topic->kind == BagTopicKind::kTrajectory;
      // Joint messages: deserialised as they are (their lists are short; a damaged count is
      // caught by the deserialiser running out of bytes, after at most one large allocation).
      const bool plausible =
          joints || topic->kind == BagTopicKind::kForeign ? true  // the decoder checks every length
          : topic->kind == BagTopicKind::kArray
              ? plausibleCount(buffer_, boxCountOffset(buffer_), min_box_bytes_, &why)
              : plausibleCount(buffer_, 0, min_transform_bytes_, &why);
      if (!plausible) throw damaged(why + " (on " + topic->name + ")");
      if (topic->kind == BagTopicKind::kJointState) {
        ros::serialization::deserialize(in, joint_state_);
      } else if (topic->kind == BagTopicKind::kTrajectory) {
        ros::serialization::deserialize(in, trajectory_);
      } else if (topic->kind == BagTopicKind::kForeign) {
        // Decoded by the input bridge from these bytes.
      } else if (topic->kind == BagTopicKind::kArray) {
        auto& pool = array_pool_[static_cast<std::size_t>(topic->source)];
        boost::shared_ptr<TrackedBoxArray>* free_slot = nullptr;
        for (auto& p : pool) {
          if (p.use_count() == 1) free_slot = &p;  // the monitor let go of it
        }
        if (free_slot == nullptr) {
          pool.push_back(boost::make_shared<TrackedBoxArray>());
          free_slot = &pool.back();
        }
        ros::serialization::deserialize(in, **free_slot);
        array = *free_slot;
      } else {
        ros::serialization::deserialize(in, tf_);
      }
    } catch (const ReplayError&) {
      throw;
    } catch (const std::exception& e) {  // rosbag's and the deserialiser's (or bad_alloc)
      throw damaged(e.what());
    }

    if (topic->kind == BagTopicKind::kJointState) {
      visitor->onJointState(joint_state_, last);
    } else if (topic->kind == BagTopicKind::kTrajectory) {
      visitor->onTrajectory(trajectory_, last);
    } else if (topic->kind == BagTopicKind::kArray) {
      visitor->onArray(topic->source, array, last);
      array.reset();
    } else if (topic->kind == BagTopicKind::kForeign) {
      visitor->onForeign(topic->source, *topic, buffer_.data(), buffer_.size(), last);
    } else {
      visitor->onTf(tf_, topic->kind == BagTopicKind::kTfStatic, last);
    }

    try {
      ++it;
    } catch (const std::exception& e) {
      throw damaged(e.what());
    }
  }
}

}  // namespace workspace_proximity

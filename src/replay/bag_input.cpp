#include "workspace_proximity/replay/bag_input.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include <ros/serialization.h>
#include <rosbag/exceptions.h>
#include <rosbag/query.h>
#include <rosbag/view.h>

#include "workspace_proximity/ros/conversions.hpp"

namespace workspace_proximity {
namespace {

constexpr char kArrayType[] = "workspace_proximity/TrackedBoxArray";

ReplayError bagError(const std::string& path, const std::string& what) {
  return ReplayError(ReplayError::kBag, "bag " + path + ": " + what);
}

// Reads the bag's file header record ("#ROSBAG V2.0\n", then op = 0x03 with index_pos,
// conn_count, chunk_count) so that the commonest damages get a message of their own before
// rosbag meets them: a recording that was never closed has index_pos = 0 (the recorder writes
// the index at the end), a copy cut short has index_pos beyond the end of the file.
void checkFileHeader(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw bagError(path, "cannot open the file (no such file, or not readable)");
  f.seekg(0, std::ios::end);
  const std::uint64_t size = static_cast<std::uint64_t>(f.tellg());
  f.seekg(0);
  char magic[13] = {};
  f.read(magic, sizeof(magic));
  const std::string version(magic, static_cast<std::size_t>(f.gcount()));
  if (version.compare(0, 9, "#ROSBAG V") != 0) {
    throw bagError(path, "not a ROS bag (it does not start with #ROSBAG)");
  }
  if (version != "#ROSBAG V2.0\n") return;  // older formats: rosbag itself says what it can do
  std::uint32_t header_len = 0;
  f.read(reinterpret_cast<char*>(&header_len), 4);
  if (!f || header_len > 4096) throw bagError(path, "truncated or damaged file header");
  std::string header(header_len, '\0');
  f.read(&header[0], header_len);
  if (!f) throw bagError(path, "truncated file header");
  std::uint64_t index_pos = 0;
  bool found = false;
  for (std::size_t at = 0; at + 4 <= header.size();) {
    std::uint32_t field_len = 0;
    std::memcpy(&field_len, header.data() + at, 4);
    at += 4;
    if (field_len > header.size() - at) break;
    const std::string field = header.substr(at, field_len);
    at += field_len;
    if (field.compare(0, 10, "index_pos=") == 0 && field.size() == 18) {
      std::memcpy(&index_pos, field.data() + 10, 8);
      found = true;
    }
  }
  if (!found) throw bagError(path, "damaged file header (no index position)");
  if (index_pos == 0) {
    throw bagError(path, "not indexed: the recording was not closed (interrupted recorder); "
                         "`rosbag reindex " + path + "` rebuilds the index");
  }
  if (index_pos >= size) {
    std::ostringstream s;
    s << "truncated: its index should start at byte " << index_pos << " but the file has only "
      << size << " bytes (an incomplete copy?); `rosbag reindex` may recover the complete part";
    throw bagError(path, s.str());
  }
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
    : path_(path), array_pool_(input_topics.size()) {
  checkFileHeader(path);
  try {
    bag_.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagUnindexedException&) {
    throw bagError(path, "not indexed (interrupted recording); `rosbag reindex " + path +
                             "` rebuilds the index");
  } catch (const rosbag::BagException& e) {
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
      const BagTopic& t = it->second;
      if (t.type != kArrayType) {
        throw bagError(path, "topic " + input + " has type " + t.type + ", not " + kArrayType);
      }
      const std::string expected = ros::message_traits::MD5Sum<TrackedBoxArray>::value();
      if (md5_of[input] != expected) {
        throw bagError(path, "topic " + input + " was recorded with another definition of " +
                                 kArrayType + " (md5 " + md5_of[input] + ", this build " +
                                 expected + "); `rosbag fix` migrates old bags");
      }
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
          t.kind == BagTopicKind::kArray) {
        replayed_.push_back(t.name);
        replayed_messages_ += t.messages;
      }
    }
  } catch (const rosbag::BagException& e) {
    throw bagError(path, std::string("cannot be read: ") + e.what());
  }
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
  } catch (const ros::Exception& e) {
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
      if (topic->kind == BagTopicKind::kArray) {
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
    } catch (const ros::Exception& e) {  // rosbag's and the deserialiser's exceptions
      throw damaged(e.what());
    }

    if (topic->kind == BagTopicKind::kArray) {
      visitor->onArray(topic->source, array, last);
      array.reset();
    } else {
      visitor->onTf(tf_, topic->kind == BagTopicKind::kTfStatic, last);
    }

    try {
      ++it;
    } catch (const ros::Exception& e) {
      throw damaged(e.what());
    }
  }
}

}  // namespace workspace_proximity

#include "workspace_proximity/ros/input_bridge.hpp"

#include <algorithm>
#include <exception>

#include <ros/console.h>
#include <tf2/exceptions.h>
#include <tf2_eigen/tf2_eigen.h>

#include "workspace_proximity/ros/conversions.hpp"

namespace workspace_proximity {

InputBridge::InputBridge(Monitor* monitor, tf2::BufferCore* tf, const std::string& fixed_frame)
    : monitor_(monitor),
      tf_(tf),
      fixed_frame_(fixed_frame),
      waiting_(static_cast<std::size_t>(monitor->sources().size())),
      foreign_(static_cast<std::size_t>(monitor->sources().size())) {}

bool InputBridge::onArray(int source, const TrackedBoxArray::ConstPtr& msg, Stamp now) {
  monitor_->noteReceipt(source, now);
  monitor_->acceptType(source);
  Waiting& w = waiting_[static_cast<std::size_t>(source)];
  if (waits(w)) {
    monitor_->drop(Drop::kSuperseded, source, "a newer array arrived before it was used");
  }
  w.foreign = false;
  w.msg = msg;
  return arrive(source, now);
}

std::uint8_t* InputBridge::foreignBytes(int source, std::size_t size) {
  std::unique_ptr<Foreign>& f = foreign_[static_cast<std::size_t>(source)];
  if (!f) {
    f = std::make_unique<Foreign>(static_cast<std::size_t>(std::max(1, monitor_->params().max_tracks)));
  }
  // The waiting message's tracks view these bytes: it is superseded before they change.
  Waiting& w = waiting_[static_cast<std::size_t>(source)];
  if (waits(w)) {
    monitor_->drop(Drop::kSuperseded, source, "a newer message arrived before it was used");
    w.msg.reset();
    w.foreign = false;
  }
  f->bytes.resize(size);  // keeps its capacity: no allocation once the largest message came
  return f->bytes.data();
}

bool InputBridge::decodeSkeleton(int source, std::string_view type, std::string_view md5,
                                 std::string_view definition, bool k4abt_markers) {
  Foreign& f = *foreign_[static_cast<std::size_t>(source)];
  if (!f.skeleton) {
    const std::size_t bones = static_cast<std::size_t>(std::max(1, monitor_->params().max_tracks));
    f.skeleton = std::make_unique<SkeletonFrame>(bones);
    f.capsules = std::make_unique<SkeletonCapsules>(bones);
  }
  SkeletonDecode result;
  ForeignRefusal refusal;
  if (type == "hri_msgs/IdsList") {
    if (!f.hri) f.hri = std::make_unique<HriIds>(f.skeleton->max_bones);
    refusal = decodeHriIds(md5, f.bytes.data(), f.bytes.size(), f.hri.get(), &result, definition);
  } else if (k4abt_markers) {
    refusal = decodeK4abtMarkers(md5, f.bytes.data(), f.bytes.size(), f.skeleton.get(), &result);
  } else {
    refusal = decodeJskSkeletons(md5, f.bytes.data(), f.bytes.size(), f.skeleton.get(), &result,
                                 definition);
  }
  if (refusal == ForeignRefusal::kUnknownMd5) {
    monitor_->refuseType(source, result.detail);
    return false;
  }
  monitor_->acceptType(source);
  if (refusal != ForeignRefusal::kNone) {
    // The whole message is lost: its bones' boxes age in the track table as missing ones do.
    monitor_->drop(Drop::kMalformed, source,
                   std::string(type) + ": " + foreignRefusalName(refusal) + ": " + result.detail);
    return false;
  }
  if (result.unread > 0) {
    // Bones named by joints no part is known for, or with a joint missing: not monitored as
    // bones this message (their earlier boxes age out), said once in a while, never silently.
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: %s: %zu bones of a %.*s not read (joint names "
                           "of no known body part, or a joint missing)",
                      monitor_->sources().source(source).name.c_str(), result.unread,
                      static_cast<int>(type.size()), type.data());
  }
  return true;
}

bool InputBridge::onForeign(int source, std::string_view type, std::string_view md5,
                            std::string_view definition, Stamp now) {
  monitor_->noteReceipt(source, now);
  Foreign& f = *foreign_[static_cast<std::size_t>(source)];
  // Skeletons: jsk's type by its name; a MarkerArray only on a topic declared to carry
  // Azure Kinect body tracking (~skeleton_marker_topics), never guessed from its content.
  const std::vector<std::string>& marker_topics = monitor_->params().skeleton_marker_topics;
  const bool k4abt = type == "visualization_msgs/MarkerArray" &&
                     std::find(marker_topics.begin(), marker_topics.end(),
                               monitor_->sources().source(source).name) != marker_topics.end();
  f.rep155 = type == "hri_msgs/IdsList";
  f.waiting_skeleton =
      k4abt || f.rep155 || type == "jsk_recognition_msgs/HumanSkeletonArray";
  if (f.waiting_skeleton) {
    if (!decodeSkeleton(source, type, md5, definition, k4abt)) {
      f.waiting_skeleton = false;
      f.rep155 = false;
      return true;
    }
    f.waiting_detections = false;
    waiting_[static_cast<std::size_t>(source)].foreign = true;
    return arrive(source, now);
  }
  const ForeignRefusal refusal = decodeForeignTracks(type, md5, f.bytes.data(), f.bytes.size(),
                                                     &f.decoded, definition);
  if (refusal == ForeignRefusal::kUnknownType || refusal == ForeignRefusal::kUnknownMd5) {
    // Never guessed at: DEGRADED, naming the type (and the layout difference), while it lasts.
    monitor_->refuseType(source, f.decoded.detail);
    return true;
  }
  monitor_->acceptType(source);
  if (refusal != ForeignRefusal::kNone) {
    monitor_->drop(Drop::kMalformed, source,
                   std::string(type) + ": " + foreignRefusalName(refusal) + ": " + f.decoded.detail);
    return true;
  }
  f.waiting_detections = f.decoded.version->family == ForeignFamily::kDetections;
  if (f.waiting_detections && !f.detections) {
    f.detections = std::make_unique<ForeignDetections>(foreignDetectionParams(monitor_->params()));
  }
  waiting_[static_cast<std::size_t>(source)].foreign = true;
  return arrive(source, now);
}

std::string_view InputBridge::foreignFrame(int source) const {
  const std::unique_ptr<Foreign>& f = foreign_[static_cast<std::size_t>(source)];
  if (f && f->waiting_skeleton) return f->rep155 ? fixed_frame_ : f->skeleton->frame_id;
  if (!f || f->decoded.refusal != ForeignRefusal::kNone) return {};
  if (!f->decoded.frame_id.empty() || f->decoded.tracks.empty()) return f->decoded.frame_id;
  return f->decoded.tracks.front().frame_id;
}

bool InputBridge::arrive(int source, Stamp now) {
  Waiting& w = waiting_[static_cast<std::size_t>(source)];
  // Work ahead while the cycle waits: at most one array per source between cycles (a flood
  // supersedes the rest, and the cycle takes the newest), and never after the clock went back
  // (the cycle resets the history first).
  if (w.taken_since_cycle || monitor_->clockWentBack(now)) return false;
  if (!take(source, now, false)) return false;
  w.taken_since_cycle = true;
  return true;
}

void InputBridge::takePending(Stamp now) {
  for (std::size_t i = 0; i < waiting_.size(); ++i) {
    waiting_[i].taken_since_cycle = false;
    if (waits(waiting_[i])) take(static_cast<int>(i), now, true);
  }
}

void InputBridge::reset() {
  for (Waiting& w : waiting_) w = Waiting();
  for (std::unique_ptr<Foreign>& f : foreign_) {
    if (!f) continue;
    f->observations.reset();  // sightings from before the jump are no velocity
    if (f->capsules) f->capsules->reset();
    f->detections.reset();    // nor tracks (made again at the next detections message)
  }
}

bool InputBridge::take(int source, Stamp now, bool at_cycle) {
  Waiting& w = waiting_[static_cast<std::size_t>(source)];
  try {
    if (!(w.foreign ? useForeign(source, now, at_cycle) : use(source, *w.msg, now, at_cycle))) {
      return false;
    }
  } catch (const std::exception& e) {
    // Never out of a callback or the cycle: the array is lost, counted and logged.
    monitor_->drop(Drop::kArrayFailure, source, e.what());
  }
  w.msg.reset();
  w.foreign = false;
  return true;
}

class InputBridge::Placement final : public ArrayPlacement {
 public:
  Placement(InputBridge* bridge, int source, const TrackedBoxArray& msg, bool at_cycle)
      : bridge_(bridge), source_(source), msg_(msg), at_cycle_(at_cycle) {}
  bool place(Stamp stamp, Eigen::Isometry3d* fixed_from_frame,
             const std::vector<BoxObservation>** boxes) override {
    if (!bridge_->lookup(source_, msg_.header.frame_id, stamp, at_cycle_, fixed_from_frame, &wait)) {
      return false;
    }
    std::vector<BoxObservation>& out = bridge_->boxes_;
    out.resize(msg_.boxes.size());
    for (std::size_t i = 0; i < msg_.boxes.size(); ++i) observe(msg_.boxes[i], &out[i]);
    *boxes = &out;
    return true;
  }
  bool wait = false;  // tf has no transform at the stamp yet: the array waits for the cycle

 private:
  InputBridge* bridge_;
  int source_;
  const TrackedBoxArray& msg_;
  bool at_cycle_;
};

bool InputBridge::use(int source, const TrackedBoxArray& msg, Stamp now, bool at_cycle) {
  const std::string& name = monitor_->sources().source(source).name;
  if (msg.header.frame_id.empty()) {
    monitor_->drop(Drop::kFrame, source, "the array has an empty frame_id");
    return true;
  }
  Stamp stamp = toStamp(msg.header.stamp);
  if (stamp == 0) {
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: array on %s has stamp 0; using the receive time",
                      name.c_str());
    stamp = monitor_->sources().source(source).last_receipt;
  }
  // The stamp is checked first, then the frame looked up (Placement); a bad stamp or frame is
  // dropped and counted, and the array is done with unless it waits for tf.
  Placement placement(this, source, msg, at_cycle);
  monitor_->ingest(source, stamp, now, &placement);
  return !placement.wait;
}

class InputBridge::ForeignPlacement final : public ArrayPlacement {
 public:
  ForeignPlacement(InputBridge* bridge, int source, const std::string& frame, bool at_cycle)
      : bridge_(bridge), source_(source), frame_(frame), at_cycle_(at_cycle) {}
  bool place(Stamp stamp, Eigen::Isometry3d* fixed_from_frame,
             const std::vector<BoxObservation>** boxes) override {
    Foreign& f = *bridge_->foreign_[static_cast<std::size_t>(source_)];
    Monitor& monitor = *bridge_->monitor_;
    if (f.rep155) {
      // REP-155: the links come from tf already in the fixed frame.
      if (!bridge_->rep155Bones(source_, stamp, at_cycle_, &wait)) return false;
      fixed_from_frame->setIdentity();
      f.capsules->convert(*f.skeleton, monitor.params(), &bridge_->boxes_);
      *boxes = &bridge_->boxes_;
      return true;
    }
    if (!bridge_->lookup(source_, frame_, stamp, at_cycle_, fixed_from_frame, &wait)) return false;
    if (f.waiting_detections) {
      // Detections: associated in the fixed frame; the tracker's confirmed tracks, with its
      // ids, velocities and errors, are the boxes (already in the fixed frame).
      if (f.detections->ingest(f.decoded, *fixed_from_frame) != DetectionRefusal::kNone) {
        monitor.drop(Drop::kOutOfOrder, source_, "detections stamped before the previous message");
        return false;
      }
      if (f.detections->skippedFrame() > 0) {
        monitor.drop(Drop::kFrame, source_,
                     std::to_string(f.detections->skippedFrame()) +
                         " detections in another frame than the message's '" + frame_ + "'");
      }
      fixed_from_frame->setIdentity();
      *boxes = &f.detections->tracks();
      return true;
    }
    if (f.waiting_skeleton) {
      // Bones: one box around each limb capsule, velocities from the joints' differences.
      f.capsules->convert(*f.skeleton, monitor.params(), &bridge_->boxes_);
      *boxes = &bridge_->boxes_;
      return true;
    }
    f.observations.convert(f.decoded, frame_, monitor.params(), &bridge_->boxes_);
    if (f.observations.skippedFrame() > 0) {
      monitor.drop(Drop::kFrame, source_,
                   std::to_string(f.observations.skippedFrame()) +
                       " tracks in another frame than the message's '" + frame_ + "'");
    }
    if (f.observations.skippedPosition() > 0) {
      monitor.drop(Drop::kPosition, source_,
                   std::to_string(f.observations.skippedPosition()) +
                       " tracks without a valid x and y (spencer: variance above 99999)");
    }
    *boxes = &bridge_->boxes_;
    return true;
  }
  bool wait = false;

 private:
  InputBridge* bridge_;
  int source_;
  const std::string& frame_;
  bool at_cycle_;
};

bool InputBridge::useForeign(int source, Stamp now, bool at_cycle) {
  Foreign& f = *foreign_[static_cast<std::size_t>(source)];
  const ForeignTrackArray& a = f.decoded;
  // The message's header; people_msgs/PositionMeasurementArray's may be empty where every
  // element has its own: then the first element's.
  std::string_view frame = f.waiting_skeleton ? f.skeleton->frame_id : a.frame_id;
  Stamp stamp = f.waiting_skeleton ? f.skeleton->stamp : a.stamp;
  if (f.rep155) {
    // An IdsList's frame says nothing (hri leaves it empty): the bodies' links come from tf.
    frame = fixed_frame_;
    stamp = f.hri->stamp;
  }
  if (!f.waiting_skeleton && !a.tracks.empty()) {
    if (frame.empty()) frame = a.tracks.front().frame_id;
    if (stamp == 0) stamp = a.tracks.front().stamp;
  }
  // The Azure Kinect driver's message while it sees nobody is an empty MarkerArray, which has
  // no header: "no bodies" as the tracker says it, placed in the fixed frame at its receipt.
  if (f.waiting_skeleton && frame.empty() && f.skeleton->bones.empty()) frame = fixed_frame_;
  if (frame.empty()) {
    monitor_->drop(Drop::kFrame, source, "the message has an empty frame_id");
    return true;
  }
  f.frame.assign(frame.data(), frame.size());
  if (stamp == 0) {
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: message on %s has stamp 0; using the receive time",
                      monitor_->sources().source(source).name.c_str());
    stamp = monitor_->sources().source(source).last_receipt;
  }
  ForeignPlacement placement(this, source, f.frame, at_cycle);
  monitor_->ingest(source, stamp, now, &placement);
  return !placement.wait;
}

bool InputBridge::rep155Bones(int source, Stamp stamp, bool at_cycle, bool* wait) {
  Foreign& f = *foreign_[static_cast<std::size_t>(source)];
  SkeletonFrame& out = *f.skeleton;
  out.bones.clear();
  out.stamp = stamp;
  out.frame_id = fixed_frame_;
  const ros::Time time = toTime(stamp);
  std::size_t missing = 0;
  for (std::string_view id : f.hri->ids) {
    Eigen::Vector3d link[kRep155LinkCount];
    bool found[kRep155LinkCount] = {};
    for (int l = 0; l < kRep155LinkCount; ++l) {
      f.link_frame.assign(rep155Link(l).data(), rep155Link(l).size());
      f.link_frame += '_';
      f.link_frame.append(id.data(), id.size());
      try {
        link[l] = tf2::transformToEigen(tf_->lookupTransform(fixed_frame_, f.link_frame, time))
                      .translation();
        found[l] = true;
      } catch (const tf2::TransformException&) {
        // On arrival tf may not have the body at the stamp yet: wait for the cycle. At the
        // cycle a link tf lacks at the stamp is missing (never an older pose as a new one).
        if (!at_cycle) {
          *wait = true;
          return false;
        }
        ++missing;
      }
    }
    for (int b = 0; b < kRep155BoneCount; ++b) {
      const Rep155Bone& bone = rep155Bone(b);
      int ia = -1, ib = -1;
      for (int l = 0; l < kRep155LinkCount; ++l) {
        if (rep155Link(l) == bone.link_a) ia = l;
        if (rep155Link(l) == bone.link_b) ib = l;
      }
      if (!found[ia] || !found[ib] || out.bones.size() >= out.max_bones) continue;
      SkeletonBone& s = out.bones.emplace_back();
      s.body_name = id;
      s.name = bone.name;
      s.part = bone.part;
      s.a = link[ia];
      s.b = link[ib];
    }
  }
  if (missing > 0) {
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: %s: %zu REP-155 link frames not in tf at the ids' "
                           "stamp: their bones are left out (kept until ~track_timeout)",
                      monitor_->sources().source(source).name.c_str(), missing);
  }
  return true;
}

bool InputBridge::lookup(int source, const std::string& frame, Stamp stamp, bool at_cycle,
                         Eigen::Isometry3d* fixed_from_frame, bool* wait) {
  try {
    *fixed_from_frame =
        tf2::transformToEigen(tf_->lookupTransform(fixed_frame_, frame, toTime(stamp)));
    return true;
  } catch (const tf2::TransformException& at_stamp) {
    // On arrival tf may simply not have caught up yet: leave the array for the cycle.
    if (!at_cycle) {
      *wait = true;
      return false;
    }
    // The newest transform is the best we have when tf lags the tracker; a frame tf cannot
    // reach at all drops the array.
    const std::string& name = monitor_->sources().source(source).name;
    try {
      *fixed_from_frame =
          tf2::transformToEigen(tf_->lookupTransform(fixed_frame_, frame, ros::Time(0)));
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: %s: no transform at the array's stamp (%s); "
                             "using the latest",
                        name.c_str(), at_stamp.what());
      return true;
    } catch (const tf2::TransformException& e) {
      ++tf_failures_;
      monitor_->drop(Drop::kFrame, source,
                     "cannot transform '" + frame + "' to '" + fixed_frame_ + "': " + e.what());
      return false;
    }
  }
}

}  // namespace workspace_proximity

#include "workspace_proximity/rules/foreign_skeletons.hpp"

#include <array>
#include <sstream>

#include "workspace_proximity/rules/ros1_wire.hpp"

namespace workspace_proximity {
namespace {

namespace ws = wire_size;

constexpr std::size_t kSegmentBytes = 2 * ws::kPoint;  // jsk_recognition_msgs/Segment
// jsk_recognition_msgs/HumanSkeleton: header, bone_names[], bones[].
constexpr std::size_t kSkeletonMin = ws::kHeaderMin + 4 + 4;
// visualization_msgs/Marker (as foreign_tracks.cpp counts it).
constexpr std::size_t kMarkerMin =
    ws::kHeaderMin + 4 + 4 + 4 + 4 + ws::kPose + ws::kPoint + 16 + 8 + 1 + 4 + 4 + 4 + 4 + 1;
constexpr std::int32_t kMarkerSphere = 2;
constexpr std::int32_t kMarkerAdd = 0;

// The joint names as the Azure Kinect ROS driver names its tf frames (k4a_ros_device.h), in
// k4abt_joint_id_t order, and each joint's parent in K4ABT's joint hierarchy (-1: the root).
constexpr std::array<std::string_view, kK4abtJointCount> kK4abtNames = {
    "Pelvis",         "Spine_Naval",    "Spine_Chest",   "Neck",          "Clavicle_left",
    "Shoulder_left",  "Elbow_left",     "Wrist_left",    "Hand_left",     "Handtip_left",
    "Thumb_left",     "Clavicle_right", "Shoulder_right", "Elbow_right",  "Wrist_right",
    "Hand_right",     "Handtip_right",  "Thumb_right",   "Hip_left",      "Knee_left",
    "Ankle_left",     "Foot_left",      "Hip_right",     "Knee_right",    "Ankle_right",
    "Foot_right",     "Head",           "Nose",          "Eye_left",      "Ear_left",
    "Eye_right",      "Ear_right"};
constexpr std::array<int, kK4abtJointCount> kK4abtParent = {
    -1, 0, 1, 2, 2, 4, 5, 6, 7, 8, 7, 2, 11, 12, 13, 14, 15, 14, 0, 18, 19, 20, 0, 22, 23, 24,
    3, 26, 26, 26, 26, 26};
// Each joint's bone to its parent, "Parent->Joint" (index 0, the root, has none).
constexpr std::array<std::string_view, kK4abtJointCount> kK4abtBones = {
    "",
    "Pelvis->Spine_Naval",        "Spine_Naval->Spine_Chest",  "Spine_Chest->Neck",
    "Spine_Chest->Clavicle_left", "Clavicle_left->Shoulder_left", "Shoulder_left->Elbow_left",
    "Elbow_left->Wrist_left",     "Wrist_left->Hand_left",     "Hand_left->Handtip_left",
    "Wrist_left->Thumb_left",     "Spine_Chest->Clavicle_right",
    "Clavicle_right->Shoulder_right", "Shoulder_right->Elbow_right", "Elbow_right->Wrist_right",
    "Wrist_right->Hand_right",    "Hand_right->Handtip_right", "Wrist_right->Thumb_right",
    "Pelvis->Hip_left",           "Hip_left->Knee_left",       "Knee_left->Ankle_left",
    "Ankle_left->Foot_left",      "Pelvis->Hip_right",         "Hip_right->Knee_right",
    "Knee_right->Ankle_right",    "Ankle_right->Foot_right",   "Neck->Head",
    "Head->Nose",                 "Head->Eye_left",            "Head->Ear_left",
    "Head->Eye_right",            "Head->Ear_right"};

template <typename... Parts>
std::string explain(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

ForeignRefusal refuse(SkeletonFrame* out, SkeletonDecode* result, ForeignRefusal reason,
                      std::string text) {
  result->refusal = reason;
  result->detail = std::move(text);
  out->bones.clear();
  return reason;
}

void begin(SkeletonFrame* out, SkeletonDecode* result) {
  out->stamp = 0;
  out->frame_id = {};
  out->bones.clear();
  if (out->bones.capacity() < out->max_bones) out->bones.reserve(out->max_bones);
  *result = SkeletonDecode();
}

// The wire reader's failure, or bytes after the end, as the refusal.
ForeignRefusal finish(WireReader& r, std::string_view what, std::size_t size, SkeletonFrame* out,
                      SkeletonDecode* result) {
  if (!r.ok()) {
    return refuse(out, result,
                  r.error() == WireError::kTruncated ? ForeignRefusal::kTruncated
                                                     : ForeignRefusal::kBadLength,
                  explain(what, ": ", r.errorText(), " (at byte ", r.offset(), " of ", size, ")"));
  }
  if (r.remaining() != 0) {
    return refuse(out, result, ForeignRefusal::kOverlong,
                  explain(what, ": ", r.remaining(), " bytes after the message's end"));
  }
  for (std::size_t i = 0; i < out->bones.size(); ++i) {
    if (!out->bones[i].a.allFinite() || !out->bones[i].b.allFinite()) {
      return refuse(out, result, ForeignRefusal::kNonFinite,
                    explain(what, ": bone ", i, " (", out->bones[i].name, "): non-finite joint"));
    }
  }
  return ForeignRefusal::kNone;
}

bool room(SkeletonFrame* out, SkeletonDecode* result) {
  if (out->bones.size() < out->max_bones) return true;
  refuse(out, result, ForeignRefusal::kTooManyTracks,
         explain("more than ", out->max_bones, " bones"));
  return false;
}

constexpr Rep155Bone kRep155Bones[kRep155BoneCount] = {
    {"body", "torso", "body->torso", BodyPart::kTorso},
    {"torso", "head", "torso->head", BodyPart::kHead},
    {"torso", "l_shoulder", "torso->l_shoulder", BodyPart::kTorso},
    {"l_shoulder", "l_elbow", "l_shoulder->l_elbow", BodyPart::kArm},
    {"l_elbow", "l_wrist", "l_elbow->l_wrist", BodyPart::kArm},
    {"torso", "r_shoulder", "torso->r_shoulder", BodyPart::kTorso},
    {"r_shoulder", "r_elbow", "r_shoulder->r_elbow", BodyPart::kArm},
    {"r_elbow", "r_wrist", "r_elbow->r_wrist", BodyPart::kArm},
    {"body", "l_hip", "body->l_hip", BodyPart::kTorso},
    {"l_hip", "l_knee", "l_hip->l_knee", BodyPart::kLeg},
    {"l_knee", "l_ankle", "l_knee->l_ankle", BodyPart::kLeg},
    {"body", "r_hip", "body->r_hip", BodyPart::kTorso},
    {"r_hip", "r_knee", "r_hip->r_knee", BodyPart::kLeg},
    {"r_knee", "r_ankle", "r_knee->r_ankle", BodyPart::kLeg},
};
constexpr std::string_view kRep155Links[kRep155LinkCount] = {
    "body",    "torso",   "head",   "l_shoulder", "l_elbow", "l_wrist", "r_shoulder", "r_elbow",
    "r_wrist", "l_hip",   "l_knee", "l_ankle",    "r_hip",   "r_knee",  "r_ankle"};

}  // namespace

const Rep155Bone& rep155Bone(int index) { return kRep155Bones[index]; }
std::string_view rep155Link(int index) { return kRep155Links[index]; }

ForeignRefusal decodeHriIds(std::string_view md5, const std::uint8_t* data, std::size_t size,
                            HriIds* out, SkeletonDecode* result, std::string_view definition) {
  constexpr std::string_view kType = "hri_msgs/IdsList";
  out->stamp = 0;
  out->frame_id = {};
  out->ids.clear();
  *result = SkeletonDecode();
  auto refuseIds = [&](ForeignRefusal reason, std::string text) {
    result->refusal = reason;
    result->detail = std::move(text);
    out->ids.clear();
    return reason;
  };
  const ForeignVersion* version = findForeignVersion(kType, md5);
  if (version == nullptr || version->format != ForeignFormat::kHriIdsList) {
    return refuseIds(ForeignRefusal::kUnknownMd5, describeUnknownMd5(kType, md5, definition));
  }
  WireReader r(data, size);
  r.u32();
  out->stamp = r.time();
  out->frame_id = r.string();
  const std::uint32_t n = r.arrayLength(4);
  for (std::uint32_t i = 0; i < n && r.ok(); ++i) {
    const std::string_view id = r.string();
    if (!r.ok()) break;
    if (id.empty() || id.find_first_of("/ \t\n") != std::string_view::npos) {
      return refuseIds(ForeignRefusal::kArrayMismatch,
                       explain(kType, ": id ", i, " '", id, "' cannot name tf frames"));
    }
    if (out->ids.size() >= out->max_ids) {
      return refuseIds(ForeignRefusal::kTooManyTracks,
                       explain(kType, ": more than ", out->max_ids, " ids"));
    }
    out->ids.push_back(id);
  }
  if (!r.ok()) {
    return refuseIds(r.error() == WireError::kTruncated ? ForeignRefusal::kTruncated
                                                        : ForeignRefusal::kBadLength,
                     explain(kType, ": ", r.errorText(), " (at byte ", r.offset(), " of ", size, ")"));
  }
  if (r.remaining() != 0) {
    return refuseIds(ForeignRefusal::kOverlong,
                     explain(kType, ": ", r.remaining(), " bytes after the message's end"));
  }
  return ForeignRefusal::kNone;
}

std::string_view k4abtJointName(int index) {
  return index >= 0 && index < kK4abtJointCount ? kK4abtNames[static_cast<std::size_t>(index)]
                                                 : std::string_view();
}

ForeignRefusal decodeJskSkeletons(std::string_view md5, const std::uint8_t* data, std::size_t size,
                                  SkeletonFrame* out, SkeletonDecode* result,
                                  std::string_view definition) {
  constexpr std::string_view kType = "jsk_recognition_msgs/HumanSkeletonArray";
  begin(out, result);
  const ForeignVersion* version = findForeignVersion(kType, md5);
  if (version == nullptr || version->format != ForeignFormat::kJskHumanSkeletonArray) {
    return refuse(out, result, ForeignRefusal::kUnknownMd5,
                  describeUnknownMd5(kType, md5, definition));
  }
  WireReader r(data, size);
  r.u32();  // seq
  out->stamp = r.time();
  out->frame_id = r.string();
  // std_msgs/Int32[] human_ids: one per skeleton, or none (jsk's own estimators leave it empty).
  const std::uint32_t ids = r.arrayLength(4);
  const std::size_t ids_at = r.offset();
  r.skip(4 * static_cast<std::size_t>(ids));
  const std::uint32_t skeletons = r.arrayLength(kSkeletonMin);
  if (r.ok() && ids != 0 && ids != skeletons) {
    return refuse(out, result, ForeignRefusal::kArrayMismatch,
                  explain(kType, ": ", ids, " human_ids for ", skeletons, " skeletons"));
  }
  for (std::uint32_t s = 0; s < skeletons && r.ok(); ++s) {
    std::uint64_t body = s;
    if (ids != 0) {
      std::int32_t id = 0;
      std::memcpy(&id, data + ids_at + 4 * static_cast<std::size_t>(s), 4);
      body = static_cast<std::uint32_t>(id);
    }
    r.u32();
    r.time();
    r.string();  // the skeleton's own header: the array's counts (one transform per message)
    const std::uint32_t names = r.arrayLength(4);
    const std::size_t names_at = r.offset();
    for (std::uint32_t i = 0; i < names && r.ok(); ++i) r.string();
    const std::uint32_t bones = r.arrayLength(kSegmentBytes);
    if (r.ok() && bones != names) {
      return refuse(out, result, ForeignRefusal::kArrayMismatch,
                    explain(kType, ": skeleton ", s, " has ", names, " bone_names for ", bones,
                            " bones"));
    }
    // The names again, now beside their segments (already checked against the bytes).
    WireReader name_reader(data + names_at, r.offset() - names_at);
    for (std::uint32_t i = 0; i < bones && r.ok(); ++i) {
      const std::string_view name = name_reader.string();
      const Eigen::Vector3d a = r.vector3();
      const Eigen::Vector3d b = r.vector3();
      const auto arrow = name.find("->");
      BodyPart part = BodyPart::kTorso;
      if (arrow == std::string_view::npos ||
          !bodyPartOfBone(name.substr(0, arrow), name.substr(arrow + 2), &part)) {
        ++result->unread;
        continue;
      }
      if (!room(out, result)) return result->refusal;
      SkeletonBone& bone = out->bones.emplace_back();
      bone.body = body;
      bone.body_id_stable = ids != 0;
      bone.name = name;
      bone.part = part;
      bone.a = a;
      bone.b = b;
    }
  }
  return finish(r, kType, size, out, result);
}

ForeignRefusal decodeK4abtMarkers(std::string_view md5, const std::uint8_t* data, std::size_t size,
                                  SkeletonFrame* out, SkeletonDecode* result) {
  constexpr std::string_view kType = "visualization_msgs/MarkerArray";
  begin(out, result);
  const ForeignVersion* version = findForeignVersion(kType, md5);
  if (version == nullptr) {
    return refuse(out, result, ForeignRefusal::kUnknownMd5, describeUnknownMd5(kType, md5, {}));
  }
  WireReader r(data, size);
  const std::uint32_t n = r.arrayLength(kMarkerMin);
  // The joints of the body being read: the driver writes each body's 32 joints in order.
  std::array<Eigen::Vector3d, kK4abtJointCount> joints;
  std::array<bool, kK4abtJointCount> seen{};
  std::int64_t body = -1;
  auto flush = [&]() {
    for (int j = 1; j < kK4abtJointCount; ++j) {
      const int parent = kK4abtParent[static_cast<std::size_t>(j)];
      if (!seen[static_cast<std::size_t>(j)] || !seen[static_cast<std::size_t>(parent)]) {
        // Missing joints: this bone is unknown this frame (the track table keeps the last).
        ++result->unread;
        continue;
      }
      const std::string_view name = kK4abtBones[static_cast<std::size_t>(j)];
      const auto arrow = name.find("->");
      BodyPart part = BodyPart::kTorso;
      bodyPartOfBone(name.substr(0, arrow), name.substr(arrow + 2), &part);
      if (!room(out, result)) return false;
      SkeletonBone& bone = out->bones.emplace_back();
      bone.body = static_cast<std::uint64_t>(body);
      bone.name = name;
      bone.part = part;
      bone.a = joints[static_cast<std::size_t>(parent)];
      bone.b = joints[static_cast<std::size_t>(j)];
    }
    seen.fill(false);
    return true;
  };
  for (std::uint32_t i = 0; i < n && r.ok(); ++i) {
    r.u32();
    const Stamp stamp = r.time();
    const std::string_view frame_id = r.string();
    r.string();  // ns
    const std::int32_t id = r.i32();
    const std::int32_t type = r.i32();
    const std::int32_t action = r.i32();
    const Eigen::Vector3d position = r.vector3();
    r.skip(32 + 24 + 16);  // orientation, scale, color
    r.duration();          // lifetime
    r.u8();                // frame_locked
    r.skipArray(ws::kPoint);
    r.skipArray(16);
    r.string();
    r.string();
    r.u8();
    if (!r.ok()) break;
    if (i == 0) {
      out->stamp = stamp;
      out->frame_id = frame_id;
    }
    if (type != kMarkerSphere || action != kMarkerAdd || frame_id != out->frame_id || id < 0) {
      return refuse(out, result, ForeignRefusal::kArrayMismatch,
                    explain(kType, " as a K4ABT skeleton: marker ", i, " (id ", id, ", type ", type,
                            ", action ", action, ", frame '", frame_id,
                            "') is not a joint SPHERE of the first marker's frame"));
    }
    const std::int64_t marker_body = id / 100;
    const int joint = id % 100;
    if (joint >= kK4abtJointCount) {
      return refuse(out, result, ForeignRefusal::kArrayMismatch,
                    explain(kType, " as a K4ABT skeleton: marker ", i, " id ", id, ": joint ",
                            joint, " is not one of K4ABT's ", kK4abtJointCount));
    }
    if (marker_body != body) {
      if (body >= 0 && !flush()) return result->refusal;
      body = marker_body;
    }
    joints[static_cast<std::size_t>(joint)] = position;
    seen[static_cast<std::size_t>(joint)] = true;
  }
  if (r.ok() && body >= 0 && !flush()) return result->refusal;
  return finish(r, kType, size, out, result);
}

}  // namespace workspace_proximity

#pragma once
/// Foreign skeleton messages (issue 24 item 4), ROS-free: one serialized message read into the
/// bones of a SkeletonFrame (skeleton_capsules.hpp), or refused with a named reason, with the
/// same rules as the tracks decoder (foreign_tracks.hpp): nothing guessed, every length checked.
///
/// - jsk_recognition_msgs/HumanSkeletonArray: one bone per Segment, named by bone_names[]
///   ("Neck->RShoulder": the part from the two joint names, bodyPartOfBone); body ids from
///   human_ids[] when it has one per skeleton, else the skeleton's index, which names no
///   track (body_id_stable false: no finite differences). Bones whose name is not "A->B" of
///   two known joints are not read (counted in `unread`).
/// - visualization_msgs/MarkerArray from the Azure Kinect ROS driver's body tracking (read as
///   a skeleton only where the topic says so: docs/node.md): one SPHERE marker per joint,
///   id = body * 100 + joint, joints in K4ABT order (k4abt_joint_id_t, 32 joints), positions in
///   m in the marker's frame. Bones join the joints as K4ABT's hierarchy does; a bone one of
///   whose joints is missing is not read (counted in `unread`).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "workspace_proximity/rules/foreign_tracks.hpp"
#include "workspace_proximity/rules/skeleton_capsules.hpp"

namespace workspace_proximity {

/// What a skeleton decode gives beside the bones.
struct SkeletonDecode {
  ForeignRefusal refusal = ForeignRefusal::kNone;
  std::string detail;      ///< the refusal explained; empty when read
  std::size_t unread = 0;  ///< bones not read (unknown joint names, missing joints)
};

/// Reads a jsk_recognition_msgs/HumanSkeletonArray with `md5` into `*out` (replacing its
/// bones; names view `data`). Returns the refusal (kUnknownMd5 naming the layout difference).
ForeignRefusal decodeJskSkeletons(std::string_view md5, const std::uint8_t* data, std::size_t size,
                                  SkeletonFrame* out, SkeletonDecode* result,
                                  std::string_view definition = {});

/// Reads a visualization_msgs/MarkerArray of Azure Kinect body-tracking joints into `*out`.
/// Markers that are not SPHEREs being added, or in another frame than the first joint's, are
/// refused (kArrayMismatch, naming the marker): a topic declared a K4ABT skeleton topic that
/// carries something else is not read as one.
ForeignRefusal decodeK4abtMarkers(std::string_view md5, const std::uint8_t* data, std::size_t size,
                                  SkeletonFrame* out, SkeletonDecode* result);

/// hri_msgs/IdsList (REP-155: /humans/bodies/tracked): the ids of the bodies tracked now.
struct HriIds {
  explicit HriIds(std::size_t max_ids = 64) : max_ids(max_ids) { ids.reserve(max_ids); }
  Stamp stamp = 0;  ///< ns
  std::string_view frame_id;
  std::vector<std::string_view> ids;  ///< views into the message's bytes
  std::size_t max_ids;
};

/// Reads an hri_msgs/IdsList into `*out`. An empty id, or one with a character that cannot be
/// part of a tf frame name ('/', white space), refuses the message (kArrayMismatch, naming it).
ForeignRefusal decodeHriIds(std::string_view md5, const std::uint8_t* data, std::size_t size,
                            HriIds* out, SkeletonDecode* result, std::string_view definition = {});

/// REP-155 bodies as ros4hri/human_description's URDF frames them: the frame of link `link` of
/// body `id` is "<link>_<id>". The bones joining frame origins, each with its part: body (the
/// hips) to torso (the shoulders' height), torso to head (the head's centre), torso to each
/// shoulder, shoulder to elbow, elbow to wrist, body to each hip, hip to knee, knee to ankle.
struct Rep155Bone {
  std::string_view link_a, link_b;
  std::string_view name;  ///< "link_a->link_b"
  BodyPart part;
};
constexpr int kRep155BoneCount = 14;
const Rep155Bone& rep155Bone(int index);
/// The links the bones use (every link_a and link_b once).
constexpr int kRep155LinkCount = 15;
std::string_view rep155Link(int index);

/// K4ABT's joint count and the name of joint `index` (as the driver's tf frames spell it).
constexpr int kK4abtJointCount = 32;
std::string_view k4abtJointName(int index);

}  // namespace workspace_proximity

#pragma once
/// Human skeletons as limb capsules as oriented boxes (issue 24 item 4), ROS-free: each bone of
/// a skeleton (two joints) is a capsule of its body part's radius, published into the monitor
/// as the capsule's tight oriented bounding box with id "<body>/<bone>" and label
/// "person/<part>", and a velocity from per-joint finite differences that bounds the speed of
/// every point of the capsule (midpoint velocity plus velocity_error). One converter per input
/// source; capacities are set up front, so converting allocates nothing once warm.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "workspace_proximity/rules/box_observation.hpp"
#include "workspace_proximity/rules/monitor_params.hpp"
#include "workspace_proximity/rules/stamp.hpp"

namespace workspace_proximity {

/// The body parts with their own label settings (config/proximity_monitor.yaml).
enum class BodyPart : std::uint8_t { kHead, kTorso, kArm, kHand, kLeg, kCount };

/// "person/head", "person/torso", "person/arm", "person/hand", "person/leg".
std::string_view bodyPartLabel(BodyPart part);

/// The part a bone between two joints belongs to, from the joints' names as the skeleton
/// trackers write them (case-insensitive: OpenPose/COCO's "RWrist", K4ABT's "WRIST_LEFT",
/// ROS4HRI's "r_wrist"): a hand when both joints are wrist/hand/thumb/finger joints; an arm
/// when one is a shoulder, elbow or wrist (clavicles count as torso); a leg when one is a
/// knee, ankle, foot or toe (hip to knee is a leg); a head when one is a nose, eye, ear or
/// head joint (neck to head is a head); a torso when both are neck/spine/chest/pelvis/hip/
/// clavicle/shoulder joints. false when a name is none of these (the bone is not read).
bool bodyPartOfBone(std::string_view joint_a, std::string_view joint_b, BodyPart* part);

/// A capsule: the points within `radius` of the segment a-b.
struct Capsule {
  Eigen::Vector3d a = Eigen::Vector3d::Zero();  ///< m
  Eigen::Vector3d b = Eigen::Vector3d::Zero();  ///< m
  double radius = 0.0;                          ///< m
};

/// The capsule's tight oriented bounding box: centred on the segment's midpoint, its z axis
/// along b - a by the shortest rotation from the frame's z (a half turn about x when b - a
/// points along -z; the identity for a sphere, a == b), full extents (2r, 2r, |b - a| + 2r). No
/// box holding the capsule is smaller along the capsule's own axes.
void capsuleBox(const Capsule& capsule, Eigen::Vector3d* centre, Eigen::Vector4d* quaternion,
                Eigen::Vector3d* dimensions);

/// The velocity of a capsule from its end joints' velocities (joints that move independently:
/// limbs stretch in tracker noise): the midpoint's velocity, and a bound on how much faster
/// than that the capsule's points can move (m/s), half the joints' velocity difference. A
/// point of the segment at s in [0, 1] moves at velocity + (s - 1/2)(velocity_b - velocity_a);
/// the capsule is the segment grown by its radius in every direction, so the capsule a time
/// t later lies within the capsule moved by velocity t and grown by spread t, turning or not.
void capsuleVelocity(const Eigen::Vector3d& velocity_a, const Eigen::Vector3d& velocity_b,
                     Eigen::Vector3d* velocity, double* spread);

/// One bone of one body, in its message's frame. Names view the message's bytes.
struct SkeletonBone {
  std::uint64_t body = 0;      ///< the body's id (jsk: human_ids[i]; K4ABT: marker id / 100)
  std::string_view body_name;  ///< a text id instead (REP-155's "<id>"), when not empty
  bool body_id_stable = true;  ///< false: the id is an index, not a track (no differences)
  std::string_view name;       ///< the bone's name, unique within its body ("Neck->RShoulder")
  BodyPart part = BodyPart::kTorso;
  Eigen::Vector3d a = Eigen::Vector3d::Zero();  ///< m, first joint
  Eigen::Vector3d b = Eigen::Vector3d::Zero();  ///< m, second joint
};

/// One decoded skeleton message: every bone of every body.
struct SkeletonFrame {
  explicit SkeletonFrame(std::size_t max_bones = 512) : max_bones(max_bones) {
    bones.reserve(max_bones);
  }
  Stamp stamp = 0;  ///< ns
  std::string_view frame_id;
  std::vector<SkeletonBone> bones;
  std::size_t max_bones;
};

class SkeletonCapsules {
 public:
  /// At most `max_bones` bones per message (a SkeletonFrame refuses more).
  explicit SkeletonCapsules(std::size_t max_bones);

  /// `in`'s bones as boxes in `*out` (resized; ids and labels view this object, valid until
  /// the next call). A bone's radius is half its part label's size_x. Its velocity is the
  /// capsule's (capsuleVelocity) from each joint's finite difference since the bone's last
  /// sighting (within params.track_timeout), velocity_error the spread (0 below 1e-7 m/s, the
  /// differences' rounding); without such a
  /// sighting, for bodies without a stable id, for a bone named twice in either message, or
  /// when the spread exceeds the label's
  /// unknownVelocitySpeed: velocity_known = false (growth at the label's max_speed).
  /// A bone missing from a message whose body is in it (a joint the tracker lost while it
  /// still tracks the person: an occluded hand) is unknown, never clear: its box from its last
  /// sighting goes out again, velocity unknown, with position_error = the label's
  /// position_error + unknownVelocitySpeed x its age (anywhere that bone could have got to
  /// since), for as long as its body is in the messages. Bones of a body that left go out no
  /// more (their tracks age out as any track's, ~track_timeout). Such boxes come after the
  /// message's own bones in `*out`.
  void convert(const SkeletonFrame& in, const MonitorParams& params,
               std::vector<BoxObservation>* out);
  /// Forgets every sighting (after the clock went back).
  void reset() { previous_.clear(); }

 private:
  struct Sighting {
    std::uint64_t key;       // hash of body and bone name
    std::uint64_t body_key;  // hash of the body alone
    Eigen::Vector3d a, b;
    Stamp stamp;             // of the message that last had this bone
    BodyPart part;
    std::uint32_t id_begin, id_size;  // its "<body>/<bone>" in sighting_ids_[its buffer]
  };
  const Sighting* findPrevious(std::uint64_t key) const;
  // Sightings of the last message (or carried over) whose bone is not in `in` but whose body
  // is: their indices in previous_, into missing_.
  void findMissing(const SkeletonFrame& in, std::size_t n);

  std::size_t max_bones_;
  std::string ids_;                   // "<body>/<bone>" of every box, back to back
  std::vector<std::size_t> id_ends_;  // end of each box's id in ids_
  std::vector<Sighting> previous_;    // sorted by key; bones seen once in their message
  std::vector<Sighting> current_;
  // The sightings' ids: current_ writes into sighting_ids_[buffer_], previous_'s are in the
  // other one (swapped with the vectors).
  std::string sighting_ids_[2];
  int buffer_ = 0;
  std::vector<std::uint64_t> present_bodies_;  // body keys of the message, sorted
  std::vector<std::uint64_t> present_bones_;   // bone keys of the message, sorted
  std::vector<std::size_t> missing_;           // indices into previous_
};

}  // namespace workspace_proximity

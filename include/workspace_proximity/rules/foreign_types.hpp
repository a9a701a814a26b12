#pragma once
/// The catalogue of foreign message types the monitor reads without their packages: each known
/// wire version of each type with its md5 and its field layout, as foreign_msgs/ stores the
/// upstream definitions (foreign_msgs/md5s.txt; test_foreign_md5s.py recomputes the md5s and
/// test_foreign_decoder checks these layouts against the stored .msg files). ROS-free.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace workspace_proximity {

/// One decoder per wire layout (several type names may share one: pedsim_msgs copies spencer's).
enum class ForeignFormat : std::uint8_t {
  kPeople,                             ///< people_msgs/People
  kPositionMeasurementArray,           ///< people_msgs/PositionMeasurementArray
  kSpencerV1,                          ///< TrackedPerson without is_matched (2015-03)
  kSpencerV2,                          ///< with is_matched (2015-04, and again since 2017-05-14)
  kSpencerV3,                          ///< with is_matched and detection_ids[] (2017-05)
  kBayesV1,                            ///< bayes_people_tracker/PeopleTracker without velocities
  kBayesV2,                            ///< with velocities (2015-08 on)
  kLegTrackerPersonArray,              ///< leg_tracker/PersonArray
  kDerivedObjectArray,                 ///< derived_object_msgs/ObjectArray
  kDerivedObjectWithCovarianceArray,   ///< derived_object_msgs/ObjectWithCovarianceArray
  kObstacles,                          ///< obstacle_detector/Obstacles (segments, circles)
  kDetection3DArray,                   ///< vision_msgs/Detection3DArray (ROS 1, 0.0.x)
  kJskBoxArrayV1,                      ///< jsk_recognition_msgs/BoundingBoxArray, no value/label
  kJskBoxArrayV2,                      ///< with value and label (2015-08 on)
  kMarkerArray,                        ///< visualization_msgs/MarkerArray (CUBE, SPHERE, CYLINDER)
  kPoseArray,                          ///< geometry_msgs/PoseArray
  kTrackedBoxArrayV1,                  ///< this package's TrackedBoxArray before per-box errors
  kJskHumanSkeletonArray,              ///< jsk_recognition_msgs/HumanSkeletonArray (bones)
  kHriIdsList,                         ///< hri_msgs/IdsList: REP-155 body ids (links from tf)
};

/// What a type carries: tracks with ids (and maybe velocities), detections to be associated, or
/// skeletons (bones as limb capsules: foreign_skeletons.hpp, not decodeForeignTracks).
enum class ForeignFamily : std::uint8_t { kTracks, kDetections, kSkeletons };

/// One known wire version of one type.
struct ForeignVersion {
  std::string_view type;     ///< "package/Type"
  std::string_view version;  ///< "v1", "v2", ... as foreign_msgs/md5s.txt names them
  std::string_view md5;      ///< 32 lowercase hex digits
  ForeignFormat format;
  ForeignFamily family;
  /// The fields ("type name" a line, constants left out) of the type, then of each nested
  /// non-standard type after a line "MSG: package/Type": the shape of ROS's own full message
  /// definition, compared field by field when an unknown md5 arrives.
  std::string_view layout;
};

/// Every known version, in foreign_msgs/md5s.txt's order.
const ForeignVersion* foreignVersions(std::size_t* count);

/// The version with this type name and md5, or nullptr.
const ForeignVersion* findForeignVersion(std::string_view type, std::string_view md5);

/// Whether any version of this type name is known.
bool isKnownForeignType(std::string_view type);

/// The explanation for a known type name with an unknown md5: the known versions and, when
/// `definition` (the publisher's full message definition, from the connection header) is
/// given, the nearest known version and the fields in which it differs.
std::string describeUnknownMd5(std::string_view type, std::string_view md5,
                               std::string_view definition);

/// The explanation for an unknown type name (lists the supported ones).
std::string describeUnknownType(std::string_view type);

/// The field differences between a message definition and a known layout ("" when the fields
/// agree), and their number in `*count`. Nested types are matched by name without package;
/// standard types (std_msgs, geometry_msgs, ...) are compared by name only.
std::string layoutDifference(std::string_view definition, std::string_view layout, int* count);

}  // namespace workspace_proximity

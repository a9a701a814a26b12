#pragma once
/// Foreign people tracks and detections, ROS-free: one serialized message of a type the
/// catalogue knows (foreign_types.hpp), identified by its type name and md5, read into neutral
/// tracks, or refused with a named reason. Nothing is guessed: an unknown md5 is never read
/// with another version's layout, every length is checked against the bytes left, reading
/// stops at the buffer's end and a message with bytes after its end is refused.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "workspace_proximity/rules/foreign_types.hpp"
#include "workspace_proximity/rules/stamp.hpp"

namespace workspace_proximity {

/// Why a message was not read.
enum class ForeignRefusal : std::uint8_t {
  kNone,
  kUnknownType,     ///< no version of this type name is known
  kUnknownMd5,      ///< the type name is known, this md5 (layout) is not
  kTruncated,       ///< the message ends inside a field
  kBadLength,       ///< a length prefix asks for more bytes than are left
  kOverlong,        ///< bytes are left after the message's last field
  kNonFinite,       ///< NaN or infinity in a value that is read
  kBadCovariance,   ///< a negative variance
  kArrayMismatch,   ///< parallel arrays (bayes_people_tracker) of different lengths
  kTooManyTracks,   ///< more tracks than the output's capacity
};

/// The refusal's name ("unknown_md5", ...), for diagnostics and counters.
const char* foreignRefusalName(ForeignRefusal refusal);

/// How a track names itself.
enum class ForeignIdKind : std::uint8_t {
  kNone,    ///< detections, obstacle_detector's segments and circles: no id at all
  kNumber,  ///< spencer, pedsim, leg_tracker, derived_object_msgs
  kText,    ///< people_msgs (name, object_id), bayes_people_tracker (uuid)
};

/// Bit i set: axis i (x, y, z) of a vector is given. kAxesNone: the vector is unknown.
constexpr std::uint8_t kAxesNone = 0;
constexpr std::uint8_t kAxesXY = 0b011;
constexpr std::uint8_t kAxesAll = 0b111;

/// One track or detection in the message's frame. Text fields view the message's bytes: they
/// are valid while that buffer is. Axes a message leaves unset read as 0 (and their
/// covariance rows and columns as 0); the masks say which are known.
struct ForeignTrack {
  ForeignIdKind id_kind = ForeignIdKind::kNone;
  std::uint64_t id_number = 0;  ///< when id_kind is kNumber
  std::string_view id_text;     ///< when id_kind is kText
  /// Class name: "person" for the people trackers, the label as given for this package's v1
  /// TrackedBoxArray, derived_object_msgs' classification ("pedestrian", "car", ...,
  /// "unknown"), "segment" for obstacle_detector's segments; empty for its circles and for
  /// vision_msgs and jsk, which give a number only.
  std::string_view label;
  bool has_label_number = false;
  std::int64_t label_number = 0;  ///< vision_msgs: the best hypothesis' id; jsk: label

  /// The element's own header where it has one (and a non-empty frame), else the array's.
  Stamp stamp = 0;  ///< ns
  std::string_view frame_id;

  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< m
  std::uint8_t position_axes = kAxesAll;
  bool has_orientation = false;
  Eigen::Vector4d quaternion = Eigen::Vector4d(0, 0, 0, 1);  ///< x, y, z, w as received
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();        ///< m/s
  std::uint8_t velocity_axes = kAxesNone;                    ///< kAxesNone: no valid velocity
  /// rad/s; only this package's own v1 TrackedBoxArray carries one (others: 0).
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  bool has_position_covariance = false;
  Eigen::Matrix3d position_covariance = Eigen::Matrix3d::Zero();  ///< m^2
  bool has_velocity_covariance = false;
  Eigen::Matrix3d velocity_covariance = Eigen::Matrix3d::Zero();  ///< m^2/s^2
  /// Full extents of the box (a circle's or cylinder's diameter), m. Unknown axes: the label's
  /// default size applies.
  Eigen::Vector3d dimensions = Eigen::Vector3d::Zero();
  std::uint8_t dimension_axes = kAxesNone;
};

/// One decoded message. Reused from message to message: the track array's capacity is set
/// once, so decoding allocates nothing (the refusal's text only is built when one happens).
struct ForeignTrackArray {
  explicit ForeignTrackArray(std::size_t max_tracks = 256) : max_tracks(max_tracks) {
    tracks.reserve(max_tracks);
  }

  const ForeignVersion* version = nullptr;  ///< the version read (nullptr when refused early)
  Stamp stamp = 0;                          ///< the array's header, ns
  std::string_view frame_id;
  std::vector<ForeignTrack> tracks;
  std::size_t max_tracks;
  std::size_t ignored = 0;  ///< elements read but not tracks (MarkerArray's other markers)
  ForeignRefusal refusal = ForeignRefusal::kNone;
  std::string detail;  ///< the refusal explained; empty when read
};

/// Reads one serialized message (ROS 1 wire format) of `type` with `md5` into `*out`
/// (replacing its contents). Returns out->refusal. `definition` is the publisher's full message
/// definition (the connection header's), used only to name the layout difference of an
/// unknown md5; it may be empty.
///
/// Validity rules honoured: spencer/pedsim's "unset if its variance exceeds 99999" per axis of
/// position, orientation and velocity; derived_object_msgs' detection_level (a velocity only
/// when OBJECT_TRACKED) and object_classified (the classification only when set); people_msgs
/// PositionMeasurement and vision/jsk detections carry no velocity; obstacle_detector's
/// segments become a midpoint, yaw and length, its circles a centre and true diameter, both
/// with x and y only and no velocity (foreign_tracks.cpp says why).
ForeignRefusal decodeForeignTracks(std::string_view type, std::string_view md5,
                                   const std::uint8_t* data, std::size_t size,
                                   ForeignTrackArray* out, std::string_view definition = {});

/// spencer_tracking_msgs' bound: a variance above it marks the axis as not set.
constexpr double kSpencerUnsetVariance = 99999.0;

}  // namespace workspace_proximity

#pragma once
/// Foreign detections (issue 24 item 3), ROS-free: a decoded message of the detections family
/// (vision_msgs/Detection3DArray, jsk_recognition_msgs/BoundingBoxArray, MarkerArray,
/// PoseArray, obstacle_detector/Obstacles; foreign_tracks.hpp)
/// through the multi-object tracker into tracks with ids, velocities and errors, in the fixed
/// frame, that the track table takes like any tracker's boxes.
///
/// What is read and what is assumed, per detection:
/// - centre and orientation from the box's pose, carried into the fixed frame by the pose of
///   the message's frame at its stamp (the tracker runs in the fixed frame, so a moving
///   sensor does not make standing people walk);
/// - full extents from the box where given and positive, else `default_dimensions`;
/// - measurement noise: the square root of the largest position variance where a covariance
///   is given, else `default_sigma`;
/// - every detection has `label` (the messages' class numbers are not names); ids are never
///   read: vision_msgs' results[].id is a class id that users overload with their own track
///   ids, so the tracker's association alone names the tracks;
/// - one stamp per message: the array's header (the elements' own headers are not used);
/// - a position without z (obstacle_detector's) stands on z = 0 of the message's frame: the
///   box's centre at half its height;
/// - obstacle_detector's segments (label "segment" in the decoded message) are tracks of
///   `segment_label`, thin boxes along the segment: `segment_size` x is the least length (a
///   shorter segment gets it), y the thickness, z the height; its circles are detections of
///   `label` with the circle's diameter as x and y.

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "workspace_proximity/rules/foreign_tracks.hpp"
#include "workspace_proximity/rules/monitor_params.hpp"
#include "workspace_proximity/rules/multi_object_tracker.hpp"

namespace workspace_proximity {

struct ForeignDetectionParams {
  std::string label = "unknown";  ///< every detection's label (the tracker's only label)
  double max_accel = 4.0;         ///< m/s^2, the label's, for the tracker's process noise
  double max_speed = 2.0;         ///< m/s, the label's, a new track's velocity sigma
  Eigen::Vector3d default_dimensions = Eigen::Vector3d(0.6, 0.6, 1.8);  ///< m, full extents
  std::string segment_label = "segment";  ///< obstacle_detector's segments' label
  double segment_max_accel = 4.0;         ///< m/s^2, that label's
  double segment_max_speed = 2.0;         ///< m/s, that label's
  /// m: x the least length, y the thickness, z the height of a segment's box.
  Eigen::Vector3d segment_size = Eigen::Vector3d(0.1, 0.1, 2.0);
  double default_sigma = 0.05;    ///< m, 1 sigma, when a detection has no covariance
  TrackerParams tracker;          ///< its labels are replaced by the two above
};

/// The monitor's parameters as the detections' tracker's: the labels `unknown` (every
/// detection, obstacle_detector's circles) and `segment` (obstacle_detector's segments) give
/// the process noise and a new track's speed where set (else 4 m/s^2 and 2 m/s), and the
/// sizes: `unknown`'s for a missing extent, `segment`'s size_x (least length), size_y
/// (thickness) and size_z (height); ~detection_tracker/ the gates, confirmation and deletion.
ForeignDetectionParams foreignDetectionParams(const MonitorParams& params);

/// Why a message gave no tracks.
enum class DetectionRefusal : std::uint8_t {
  kNone,
  kNotDetections,  ///< a refused decode, or a type of the tracks family
  kOutOfOrder,     ///< stamped before the previous message
};

class ForeignDetections {
 public:
  /// Throws std::invalid_argument on bad tracker parameters (validate(TrackerParams)).
  explicit ForeignDetections(const ForeignDetectionParams& params);

  /// One decoded message, its frame posed `fixed_from_frame` in the fixed frame at its stamp.
  /// Allocation-free once warm (up to the tracker's max_detections).
  DetectionRefusal ingest(const ForeignTrackArray& array, const Eigen::Isometry3d& fixed_from_frame);

  /// Detections of the last ingest() skipped because their own header names another frame
  /// than the message's (its header's, or where that is empty its first element's): one
  /// message, one transform, so they are never placed with another frame's pose.
  std::size_t skippedFrame() const { return skipped_frame_; }

  /// The confirmed tracks after the last ingest(), in the fixed frame at stamp() (views into
  /// the tracker: valid until the next ingest()).
  const std::vector<BoxObservation>& tracks() const { return tracker_.tracks(); }
  Stamp stamp() const { return tracker_.stamp(); }
  const MultiObjectTracker& tracker() const { return tracker_; }

 private:
  ForeignDetectionParams params_;
  MultiObjectTracker tracker_;
  std::vector<Detection> detections_;
  std::size_t skipped_frame_ = 0;
};

}  // namespace workspace_proximity

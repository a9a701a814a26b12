#include "workspace_proximity/rules/foreign_detections.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "workspace_proximity/body.hpp"

namespace workspace_proximity {
namespace {

TrackerParams trackerParams(const ForeignDetectionParams& p) {
  TrackerParams t = p.tracker;
  t.labels.assign(1, TrackerLabel{p.label, p.max_accel, p.max_speed});
  t.labels.push_back(TrackerLabel{p.segment_label, p.segment_max_accel, p.segment_max_speed});
  return t;
}

// m: the detection's 1 sigma. The largest variance of a given covariance: the tracker's noise
// is isotropic, so the worst axis speaks for all.
double sigmaOf(const ForeignTrack& t, double fallback) {
  if (!t.has_position_covariance) return fallback;
  const double largest = t.position_covariance.diagonal().maxCoeff();
  return largest > 0.0 ? std::sqrt(largest) : fallback;
}

// The decoder's name for obstacle_detector's segments (foreign_tracks.cpp).
constexpr std::string_view kSegment = "segment";
constexpr int kDetectionLabel = 0, kSegmentLabel = 1;  // indices into the tracker's labels

}  // namespace

ForeignDetectionParams foreignDetectionParams(const MonitorParams& params) {
  ForeignDetectionParams p;
  const LabelSettings& unknown = params.label(p.label);
  if (unknown.max_accel > 0.0) p.max_accel = unknown.max_accel;
  if (unknown.max_speed > 0.0) p.max_speed = unknown.max_speed;
  p.default_dimensions = Eigen::Vector3d(unknown.size_x, unknown.size_y, unknown.size_z);
  const LabelSettings& segment = params.label(p.segment_label);
  if (segment.max_accel > 0.0) p.segment_max_accel = segment.max_accel;
  if (segment.max_speed > 0.0) p.segment_max_speed = segment.max_speed;
  p.segment_size = Eigen::Vector3d(segment.size_x, segment.size_y, segment.size_z);
  const DetectionTrackerSettings& t = params.detection_tracker;
  p.tracker.gate_chi2 = t.gate_chi2;
  p.tracker.gate_distance = t.gate_distance;
  p.tracker.confirm_hits = t.confirm_hits;
  p.tracker.max_misses = t.max_misses;
  p.tracker.timeout = t.timeout;
  p.tracker.known_velocity_error = t.known_velocity_error;
  return p;
}

ForeignDetections::ForeignDetections(const ForeignDetectionParams& params)
    : params_(params), tracker_(trackerParams(params)) {
  detections_.reserve(static_cast<std::size_t>(params_.tracker.max_detections));
}

DetectionRefusal ForeignDetections::ingest(const ForeignTrackArray& array,
                                           const Eigen::Isometry3d& fixed_from_frame) {
  if (array.refusal != ForeignRefusal::kNone || array.version == nullptr ||
      array.version->family != ForeignFamily::kDetections) {
    return DetectionRefusal::kNotDetections;
  }
  const Eigen::Matrix3d rotation = fixed_from_frame.linear();
  const Eigen::Quaterniond frame_rotation(rotation);
  detections_.clear();
  skipped_frame_ = 0;
  // The message's frame as the input bridge places it: its header's, else its first element's.
  const std::string_view frame = !array.frame_id.empty() || array.tracks.empty()
                                     ? array.frame_id
                                     : array.tracks.front().frame_id;
  const std::size_t room = static_cast<std::size_t>(params_.tracker.max_detections);
  for (const ForeignTrack& t : array.tracks) {
    if (detections_.size() >= room) break;  // the tracker would drop them: counted there
    if (t.frame_id != frame) {
      ++skipped_frame_;
      continue;
    }
    Detection d;
    const bool segment = t.label == kSegment;
    Eigen::Vector3d centre = t.position;
    if (segment) {
      // A thin box along the segment: its length (at least the least one), the label's
      // thickness and height.
      d.dimensions = params_.segment_size;
      d.dimensions.x() = std::max(t.dimensions.x(), params_.segment_size.x());
    } else {
      for (int k = 0; k < 3; ++k) {
        const bool given = (t.dimension_axes >> k) & 1;
        const double size = t.dimensions[k];
        // A flat or missing extent is no extent: the label's default holds an object there.
        d.dimensions[k] = given && size >= 2.0 * Limits::kMinSize ? size
                                                                  : params_.default_dimensions[k];
      }
    }
    // No height measured: the object stands on the frame's z = 0.
    if ((t.position_axes & 0b100) == 0) centre.z() = 0.5 * d.dimensions.z();
    d.position = fixed_from_frame * centre;
    Eigen::Quaterniond q = frame_rotation;
    if (t.has_orientation) {
      const Eigen::Vector4d& v = t.quaternion;
      const Eigen::Quaterniond own(v.w(), v.x(), v.y(), v.z());
      // A zero quaternion (unset) means no rotation. Any other keeps its length, so the
      // tracker rejects one that is not of unit length (counted) rather than guess.
      q = own.norm() > 0.0 ? frame_rotation * own : frame_rotation;
    }
    d.quaternion = Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
    d.sigma = sigmaOf(t, params_.default_sigma);
    d.label = segment ? kSegmentLabel : kDetectionLabel;
    detections_.push_back(d);
  }
  // The tracker counts what it drops or rejects; ids in the message are never read.
  if (!tracker_.update(array.stamp, detections_)) return DetectionRefusal::kOutOfOrder;
  return DetectionRefusal::kNone;
}

}  // namespace workspace_proximity

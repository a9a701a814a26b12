#pragma once
/// The clusters of every sensor's frames as tracks (issue 23), ROS-free: the glue between
/// CloudFrame's per-frame detections (voxel_clusters.hpp, fixed frame, no ids, no velocity)
/// and the one MultiObjectTracker (multi_object_tracker.hpp, the tracker the monitor's
/// detection inputs use) whose confirmed tracks cloud_tracker publishes as TrackedBoxArray.
///
/// Several sensors, one tracker: each sensor's frame is associated into the same tracker in
/// the order frames arrive, at its own stamp. A frame stamped before the tracker's newest
/// frame (a sensor whose frames come later than another's) is not dropped: it is applied at
/// the tracker's stamp, its centres' noise grown by what the object may have moved in
/// between, `max_speed` x the gap taken as a 3 sigma bound (sigma^2 += (max_speed gap / 3)^2);
/// a gap beyond `max_merge_gap` drops the frame (counted). Nothing waits: no latency is
/// added to merge sensors.
///
/// Sensors of different vertical coverage see one object differently: a depth camera's
/// cluster of a person is the whole body, a floor scanner's is the legs extruded over the
/// scan band, so their centres and sizes differ. Association is therefore by footprint
/// (TrackerParams::gate_footprint: (x, y) distances, overlapping footprints gate), and a
/// track's published box is the union of what each sensor saw of it in that sensor's latest
/// frame: the tracker's box (the last detection's size at the filtered centre) and, for every
/// sensor whose latest frame matched the track (this frame's sensor included), that
/// detection's box kept where it was relative to the filtered centre (moving with the track).
/// Nothing a sensor sees of an object disappears at another sensor's frame; with one sensor
/// the box is the filtered box and the detection together.
///
/// One object may come as several clusters of one frame (a person cut by the arm's shadow, a
/// scanner's beams on one body with gaps): clusters of one frame whose footprints overlap or
/// are at most `fragment_gap` apart in x and in y are one detection, their boxes' union
/// (nothing is dropped: the union holds every point of each), so a fragment does not start a
/// track of its own each frame.
///
/// A fragment may also lie farther than `fragment_gap` from the rest of its object (a floor
/// scanner's single beam on a person's far corner, the arm's shadow cutting a forklift in two)
/// and would then start a second track beside the object's own, every frame anew (issue 23,
/// demo3: four of every five tracks the demo started were such duplicates). So, with
/// `merge_within_tracks`, one frame's detections whose (x, y) footprints lie wholly inside one
/// live track's footprint are one detection, their union; inside several tracks' footprints,
/// the oldest track's. A track's footprint is made of its cores, not of its published box: for
/// every sensor whose latest frame saw it, a core (where it was seen), moved by the track's
/// velocity when known and grown by its 3 sigma position error plus its velocity error (or
/// `max_speed` while unknown) times the time since. A frame's core is the largest cluster the
/// track got from it, with those of its clusters that lay inside the last cores grown by the
/// velocity error part alone: a core grows no faster than the track's stated motion, and what
/// only the position error's allowance took in stays out of it. (The published box holds what
/// merges took in; a footprint made from it, with an allowance every frame, would follow
/// anything moving away at up to allowance / period: a person walking away from the forklift
/// would drag its box along.) Nothing is dropped; a detection reaching out of every footprint
/// keeps its own track.
///
/// Every cluster is one detection of label `label` (the monitor's `unknown`: a cluster has no
/// class), its axis-aligned box, 1 sigma centre noise `sigma` per axis. A track's velocity is
/// unknown (velocity_known false: the monitor grows it at the label's max_speed) until its
/// filter's 3 sigma velocity error is at most `tracker.known_velocity_error`; then its
/// 3 sigma position and velocity errors go with it.
///
/// Capacities set up front; update() allocates nothing once warm.

#include <cstdint>
#include <string>
#include <vector>

#include "workspace_proximity/perception/voxel_clusters.hpp"
#include "workspace_proximity/rules/multi_object_tracker.hpp"

namespace workspace_proximity {
namespace perception {

struct ClusterTrackParams {
  std::string label = "unknown";  ///< every track's label (the monitor's settings for it)
  double max_accel = 4.0;         ///< m/s^2, the label's: the filter's process noise (3 sigma)
  double max_speed = 2.0;         ///< m/s, the label's: a new track's velocity sigma, late frames
  double sigma = 0.05;            ///< m, 1 sigma noise of a cluster's centre per axis
  double max_merge_gap = 0.2;     ///< s: a frame older than the tracker's newest by more is dropped
  int sensors = 1;                ///< sensors whose frames come in (update()'s `sensor` < this)
  bool merge_fragments = true;    ///< one frame's clusters with near footprints are one detection
  double fragment_gap = 0.1;      ///< m, footprints at most this far apart in x and y merge
  bool merge_within_tracks = true;  ///< one frame's detections inside one track's footprint are one
  /// The tracker's gating and life (its labels are replaced by the one above). Defaults for
  /// clusters: a cluster is a track from its first frame (confirm_hits 1: unknown is never
  /// clear), and a track no sensor saw in `max_misses` frames in a row is gone.
  TrackerParams tracker = defaultTrackerParams();
  static TrackerParams defaultTrackerParams() {
    TrackerParams t;
    t.confirm_hits = 1;
    t.max_misses = 1;
    t.id_prefix = "c";
    t.gate_footprint = true;
    return t;
  }
};

/// Problems with `params`, one message each naming the field; empty when usable.
std::vector<std::string> validate(const ClusterTrackParams& params);

/// What the last update() did with its frame.
enum class ClusterFrameUse : std::uint8_t {
  kUsed,      ///< at its own stamp
  kLate,      ///< at the tracker's newer stamp, its noise grown
  kTooLate,   ///< older than the tracker's newest by more than max_merge_gap: dropped
};

class ClusterTracks {
 public:
  /// Throws std::invalid_argument when validate(params) finds a problem.
  explicit ClusterTracks(const ClusterTrackParams& params);

  /// One frame of sensor `sensor` (0 .. sensors - 1): its clusters (fixed frame) at `stamp` (ns).
  ClusterFrameUse update(Stamp stamp, const std::vector<Detection>& clusters, int sensor = 0);
  /// The confirmed tracks after the last update, in the fixed frame at stamp(), each box the
  /// union of every sensor's latest sight of it (ids and labels are views into the tracker:
  /// valid until the next update()).
  const std::vector<BoxObservation>& tracks() const { return output_; }
  /// The tracker's newest frame stamp (ns): the tracks' stamp.
  Stamp stamp() const { return tracker_.stamp(); }
  const MultiObjectTracker& tracker() const { return tracker_; }
  /// Frames applied late (kLate) and dropped (kTooLate) so far.
  long late() const { return late_; }
  long tooLate() const { return too_late_; }
  /// Clusters beyond the tracker's max_detections, so far (not tracked: the node reports it).
  long overflow() const { return overflow_; }
  /// Detections merged into another of their frame because both lay inside one track's
  /// footprint (merge_within_tracks), so far.
  long mergedWithinTracks() const { return merged_within_tracks_; }

 private:
  ClusterTrackParams params_;
  MultiObjectTracker tracker_;
  void unite(int sensor, Stamp stamp);
  void mergeFragments(Stamp stamp);
  void linkWithinTracks(Stamp stamp);
  int root(int i);

  std::vector<workspace_proximity::Detection> detections_;
  std::vector<int> parent_;  // per detection: union-find over near footprints
  std::vector<Eigen::Vector3d> lo_, hi_;  // per detection: its box's corners
  std::vector<int> first_in_track_;  // per published track (last frame): its first detection inside
  std::vector<Eigen::Vector3d> core_lo_, core_hi_;  // per detection: its largest member's box
  std::vector<std::uint8_t> tight_;  // per detection: inside its track's cores grown by velocity only
  std::vector<Eigen::Vector3d> track_lo_, track_hi_, tight_lo_, tight_hi_;  // per track: footprints
  // Per (slot, sensor), flat at slot * sensors + sensor: that sensor's last box of the track
  // (corners relative to the filtered centre), the track's id then, and the frame's stamp.
  std::vector<std::uint64_t> sight_id_;
  std::vector<Stamp> sight_stamp_;
  std::vector<Eigen::Vector3d> sight_min_, sight_max_;
  std::vector<Eigen::Vector3d> core_min_, core_max_;  // that detection's core, fixed frame
  std::vector<Stamp> sensor_stamp_;  // per sensor: its latest frame's (applied) stamp
  std::vector<BoxObservation> output_;
  long late_ = 0;
  long too_late_ = 0;
  long overflow_ = 0;
  long merged_within_tracks_ = 0;
};

}  // namespace perception
}  // namespace workspace_proximity

#pragma once
/// A small multi-object tracker for sources that report detections without ids or velocities
/// (point cloud clusters, vision_msgs/Detection3DArray, jsk BoundingBoxArray, MarkerArray,
/// PoseArray): detections in, tracks with stable ids, velocities and honest errors out, as
/// BoxObservations the track table takes like any tracker's boxes. ROS-free.
///
/// Per frame (one stamp, every detection in one frame of reference):
/// 1. Every live track is predicted to the frame's stamp with a constant-velocity Kalman filter
///    (state: centre and velocity; the three axes share one 2 x 2 covariance, since the
///    measurement noise is isotropic and the process noise is the same on every axis). Process
///    noise: white acceleration, sigma_a = max_accel / 3 of the track's label (the label's
///    bound taken as 3 sigma), discrete form Q = sigma_a^2 [dt^4/4, dt^3/2; dt^3/2, dt^2].
/// 2. Gating: a detection may update a track of its own label whose predicted centre is within
///    `gate_distance` m and whose squared Mahalanobis distance d^2 = |z - x|^2 / (P_pp + sigma^2)
///    is at most `gate_chi2` (chi-square, 3 degrees of freedom: 16.27 keeps 99.9 % of true
///    detections).
///    With `gate_footprint` (sensors of different vertical coverage, e.g. a depth camera's
///    whole person and a floor scanner's legs extruded over a height band, into one tracker):
///    the distances are taken in (x, y) only, and a pair within `gate_distance` also gates
///    when the detection's footprint (its box's x, y extent) overlaps the track's footprint
///    grown by its 3 sigma position error 3 sqrt(P_pp); such a pair costs at most gate_chi2.
///    Its update takes the detection's noise grown to put it on the gate (sigma^2 >=
///    |z - x|^2 / gate_chi2 - P_pp): a centre offset between sensors is taken as noise, not
///    as a velocity.
/// 3. Assignment: an optimal one on the gated cost matrix (Hungarian method, shortest
///    augmenting paths with potentials, O(n^2 m)): first as many gated pairs as possible, then
///    the least total d^2 among those (a gated-out pair costs more than every gated total).
/// 4. Update: a matched track takes its detection (Kalman update; dimensions and orientation
///    as detected), an unmatched one coasts (its prediction, with its grown covariance). A
///    detection left over starts a tentative track with unknown velocity (initial velocity
///    sigma: the label's max_speed).
/// 5. Life: tentative -> confirmed after `confirm_hits` hits; deleted after `max_misses` frames
///    in a row without a detection, or when its last detection is older than `timeout`.
/// Output: every confirmed track at the frame's stamp (coasting ones too, predicted), with
/// position_error = 3 sqrt(P_pp), velocity_error = 3 sqrt(P_vv), and velocity_known once
/// velocity_error <= `known_velocity_error` (again false if it grows beyond it while
/// coasting). Ids are "<prefix><n>", n counting up from 1, never reused.
///
/// Capacities are set up front (`capacity` tracks, `max_detections` per frame); state lives in
/// flat arrays addressed by slot; update() allocates nothing.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "workspace_proximity/rules/box_observation.hpp"
#include "workspace_proximity/rules/stamp.hpp"

namespace workspace_proximity {

/// One detection of a frame, in the frame of reference of every detection of the frame.
struct Detection {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();        ///< centre, m
  Eigen::Vector3d dimensions = Eigen::Vector3d::Ones();      ///< full edges, m
  Eigen::Vector4d quaternion = Eigen::Vector4d(0, 0, 0, 1);  ///< x, y, z, w
  int label = 0;       ///< index into TrackerParams::labels
  double sigma = 0.05; ///< m, 1 sigma measurement noise of the centre, per axis
};

/// The quaternion (x, y, z, w) of a rotation by `yaw` rad about z.
Eigen::Vector4d yawQuaternion(double yaw);

/// A class of objects as the tracker treats them.
struct TrackerLabel {
  std::string name = "unknown";  ///< the tracks' label (selects the monitor's settings)
  double max_accel = 4.0;        ///< m/s^2, 3 sigma of the filter's white acceleration
  double max_speed = 2.0;        ///< m/s, 1 sigma of a new track's unknown velocity
};

struct TrackerParams {
  int capacity = 256;          ///< live tracks at most (tentative ones included)
  int max_detections = 512;    ///< detections used per frame (the rest are counted, dropped)
  double gate_chi2 = 16.27;    ///< squared Mahalanobis distance gate (3 dof, 99.9 %)
  double gate_distance = 2.0;  ///< m, metric gate on |detection - predicted centre|
  int confirm_hits = 2;        ///< detections that confirm a tentative track (1: at once)
  int max_misses = 3;          ///< frames in a row without a detection that delete a track
  double timeout = 1.0;        ///< s since its last detection that delete a track
  double known_velocity_error = 1.0;  ///< m/s, 3 sigma: the velocity is known at or below
  std::string id_prefix = "t";        ///< ids are id_prefix + a number (at most 15 chars)
  bool gate_footprint = false;  ///< gate in (x, y), footprints overlapping (step 2 above)
  std::vector<TrackerLabel> labels{TrackerLabel()};  ///< at least one
};

/// Problems with `params`, one message each naming the field; empty when usable.
std::vector<std::string> validate(const TrackerParams& params);

/// What the last update() did.
struct TrackerStats {
  int detections = 0;  ///< used
  int rejected = 0;    ///< invalid (non-finite, bad sigma, dimensions or label)
  int dropped = 0;     ///< beyond max_detections, or no room for a new track
  int matched = 0;     ///< detections that updated a track
  int born = 0;        ///< tentative tracks started
  int deleted = 0;     ///< tracks deleted (misses or timeout)
  int live = 0;        ///< live tracks after the frame (tentative and confirmed)
};

/// The least-cost assignment of rows to columns (Hungarian method, shortest augmenting paths
/// with potentials, O(n^2 m) for n = min(rows, cols)): every row of the smaller side gets a
/// distinct column of the other. Work arrays sized up front for `max_side`.
class OptimalAssignment {
 public:
  explicit OptimalAssignment(int max_side);
  /// `cost` is rows x cols, row-major (rows, cols <= max_side). `row_match[r]` receives the
  /// column of row r, or -1 (rows beyond the columns' count when rows > cols). Allocation-free.
  void solve(const double* cost, int rows, int cols, int* row_match);

 private:
  std::vector<double> u_, v_, minv_;
  std::vector<int> p_, way_;
  std::vector<std::uint8_t> done_;
};

class MultiObjectTracker {
 public:
  /// Throws std::invalid_argument when validate(params) finds a problem.
  explicit MultiObjectTracker(const TrackerParams& params);

  /// One frame of `count` detections at `stamp`. False (nothing changes) when the stamp is
  /// older than the previous frame's. Allocation-free.
  bool update(Stamp stamp, const Detection* detections, int count);
  bool update(Stamp stamp, const std::vector<Detection>& detections) {
    return update(stamp, detections.data(), static_cast<int>(detections.size()));
  }
  /// Forgets every track (ids keep counting up).
  void clear();

  /// The confirmed tracks at the last frame's stamp (views into this tracker: valid until the
  /// next update() or clear()).
  const std::vector<BoxObservation>& tracks() const { return output_; }
  /// The slot of output track i (for slotOf-style lookups in tests and bridges).
  int outputSlot(int i) const { return output_slot_[static_cast<std::size_t>(i)]; }
  /// The numeric id of the track in `slot` (0: free slot).
  std::uint64_t idOfSlot(int slot) const { return id_[static_cast<std::size_t>(slot)]; }
  /// The index (into the last update()'s detections) of the detection the track in `slot`
  /// took or was born from in the last update, -1 when it coasted.
  int detectionOfSlot(int slot) const { return detection_of_[static_cast<std::size_t>(slot)]; }
  const TrackerStats& stats() const { return stats_; }
  const TrackerParams& params() const { return params_; }
  Stamp stamp() const { return stamp_; }

 private:
  enum : std::uint8_t { kFree = 0, kTentative = 1, kConfirmed = 2 };
  bool validDetection(const Detection& d) const;
  void predict(int slot, double dt);
  void correct(int slot, const Detection& d);
  bool footprintsOverlap(std::size_t s, const Detection& d) const;
  int birth(const Detection& d);
  void release(int slot);
  void publish();

  TrackerParams params_;
  Stamp stamp_ = 0;
  bool started_ = false;
  std::uint64_t next_id_ = 1;
  TrackerStats stats_;

  // Per slot (capacity), flat.
  std::vector<std::uint8_t> state_;
  std::vector<std::uint64_t> id_;
  std::vector<std::string> id_text_;  // reserved up front: assign() never allocates
  std::vector<int> label_;
  std::vector<int> hits_;
  std::vector<int> misses_;
  std::vector<Stamp> seen_;  // stamp of the last detection
  std::vector<int> detection_of_;  // the last update's detection index, -1: coasted
  std::vector<Eigen::Vector3d> position_;
  std::vector<Eigen::Vector3d> velocity_;
  std::vector<Eigen::Vector3d> dimensions_;
  std::vector<Eigen::Vector4d> quaternion_;
  std::vector<double> p_pp_, p_pv_, p_vv_;  // the shared per-axis covariance, m^2, m^2/s, m^2/s^2
  std::vector<int> free_;  // free slots, a stack
  std::vector<int> live_;  // live slots, dense (order of birth, swap-removed)

  // Per frame, reused.
  std::vector<int> used_;          // indices of the detections used
  std::vector<double> cost_;       // live x used, row-major
  std::vector<int> match_of_row_;  // per live track: used-detection index or -1
  std::vector<int> matched_det_;   // per used detection: 1 when matched
  OptimalAssignment assignment_;

  std::vector<BoxObservation> output_;
  std::vector<int> output_slot_;
};

}  // namespace workspace_proximity

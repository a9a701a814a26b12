#pragma once
/// What no sensor saw this frame. The protective volume is the voxels within R (the speed
/// and separation reach) of the robot, outside the padded robot itself and above the floor.
/// A protective voxel is seen when at least one sensor has its centre inside its field of
/// view and range, and the straight line from that sensor to the centre crosses no voxel of
/// that sensor's frame holding a point (anything: a person, the robot, the floor) or a shadow
/// cast from outside the volume. The rest is unseen: behind the robot, behind a person, or
/// outside every field of view; unknown space is never read as clear.
///
/// Not covered: a ray with no return (a NaN pixel, black clothing, dropout) says nothing here,
/// so the voxels along it count as seen when nothing else blocks them; the dropped points are
/// counted in CloudFrameStats::non_finite instead. ROS-free; allocation-free after configure().

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "workspace_proximity/perception/self_filter.hpp"
#include "workspace_proximity/perception/voxel_grid.hpp"

namespace workspace_proximity {
namespace perception {

/// A sensor's field of view. Its frame looks along +x with z up (REP 103's body convention;
/// a camera's optical frame is turned into it by the caller).
struct SensorFov {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor frame in the fixed frame
  double azimuth_min = -0.5;    ///< rad, atan2(y, x) in the sensor frame
  double azimuth_max = 0.5;     ///< rad
  double elevation_min = -0.4;  ///< rad, atan2(z, hypot(x, y))
  double elevation_max = 0.4;   ///< rad
  double range_min = 0.0;       ///< m
  double range_max = 10.0;      ///< m
};

/// One sensor's latest frame: its field of view and the grid its cloud was voxelized into
/// (CloudFrame::grid(); every sensor's grid must have the geometry given to configure()).
struct SensorSight {
  SensorFov fov;
  const VoxelGrid* grid = nullptr;
};

struct UnseenResult {
  std::int64_t protective = 0;   ///< protective voxels this frame
  std::int64_t unseen = 0;       ///< of them, seen by no sensor
  std::int64_t outside_fov = 0;  ///< unseen and outside every field of view
  std::int64_t shadowed = 0;     ///< unseen, inside some field of view but blocked in each
  double share = 0.0;            ///< unseen / protective (0 with no protective voxel)
  std::int64_t walks = 0;        ///< lines of sight walked voxel by voxel (work done)
  /// The inputs were refused (a link not finite or invalid, a reach or padding not finite
  /// or negative): the protective volume is unknown, and the share is 1.
  bool refused = false;
};

/// rad: the largest error of fastAtan2 (test_unseen_share checks it against std::atan2).
constexpr float kFastAtan2Error = 2e-5f;
/// atan2 by a polynomial, within kFastAtan2Error of std::atan2 (0 at the origin).
float fastAtan2(float y, float x);

/// Per sensor, a depth image in azimuth and elevation first says which protective voxels
/// have nothing in front of them (seen at once) and which certainly have (blocked at once);
/// only the others walk their line of sight voxel by voxel. The images only skip walks: the
/// answer is the walk's.
class UnseenShare {
 public:
  /// `max_bins`: size of the depth image (bins of `bin_angle` rad, coarser when a field of
  /// view needs more).
  explicit UnseenShare(int max_sensors, std::int64_t max_bins = 1 << 20, double bin_angle = 0.004);

  /// Takes the grid's geometry (cells, size, origin) and sizes the work arrays (allocates).
  void configure(const VoxelGrid& geometry);

  /// The share for the robot `links` (posed now), reach `reach` (R, m), robot padding
  /// `padding` (m), floor `floor_z` (m: cells whose centre is below are not protective) and
  /// the sensors' latest frames. With no sensor every protective voxel is unseen.
  const UnseenResult& compute(const SelfLink* links, int link_count, double reach, double padding,
                              double floor_z, const SensorSight* sensors, int sensor_count);

  const UnseenResult& result() const { return result_; }
  /// The unseen voxels of the last compute() (cell indices of the grid), e.g. to treat them as
  /// occupied (~unseen: occupied).
  const std::vector<std::int64_t>& unseenCells() const { return unseen_cells_; }
  /// The protective voxels of the last compute().
  const std::vector<std::int64_t>& protectiveCells() const { return protective_; }

  /// Whether the straight line from `from` (fixed frame) to the centre of `cell` crosses a
  /// voxel of `grid` with a point or a shadow (the cell itself and the voxel holding `from`
  /// excepted; a cell holding only a shadow is blocked). Public for tests. `until`: the walk
  /// stops (not blocked) before entering a voxel beyond this fraction of the way to `from`
  /// (when nothing blocking can lie nearer `from` than that).
  static bool blocked(const VoxelGrid& grid, const Eigen::Vector3d& from, std::int64_t cell,
                      double until = 1.0);
  /// Whether `p` (fixed frame) is inside the field of view and range, by a margin: within
  /// kFastAtan2Error of an angular limit or 0.1 mm of a range limit counts as outside.
  static bool inView(const SensorFov& fov, const Eigen::Vector3d& p);

 private:
  // Fills depth_ for one sensor: per bin the nearest range at which a voxel with a point or a
  // shadow could cross a line of sight through that bin.
  void fillDepth(const SensorSight& sight, const Eigen::Isometry3d& to_sensor);
  std::int64_t binOf(double azimuth, double elevation) const;

  int max_sensors_;
  std::int64_t max_bins_;
  double bin_angle_;
  // The depth image of the sensor at hand: bins of bin_ rad from (az0_, el0_).
  std::vector<float> depth_;
  // Per bin the range beyond which a line of sight through any part of the bin has certainly
  // crossed a blocking voxel (its inscribed sphere covers the whole bin): blocked, no walk.
  std::vector<float> inner_;
  double bin_ = 0.0, az0_ = 0.0, el0_ = 0.0;
  std::int64_t naz_ = 0, nel_ = 0;
  bool all_near_ = false;  // a voxel around the sensor itself: every line of sight is walked
  std::vector<std::uint8_t> seen_;  // per protective voxel
  VoxelGrid geometry_{0};
  std::vector<std::uint8_t> mark_;          // per cell: 1 within reach, 2 inside the padded robot
  std::vector<std::int64_t> marked_;        // cells with a mark, to reset
  std::vector<std::int64_t> protective_;
  std::vector<std::int64_t> unseen_cells_;
  UnseenResult result_;
};

}  // namespace perception
}  // namespace workspace_proximity

#pragma once
/// One cloud, in to detections out: points to the fixed frame, NaNs dropped and counted,
/// crop to the monitored volume, floor removal, the self-filter, voxels, clusters. Each
/// frame stands alone: a person who leaves is gone in the next frame. ROS-free; capacities
/// set up front, no allocation per frame once configured.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "workspace_proximity/aabb.hpp"
#include "workspace_proximity/perception/cloud_input.hpp"
#include "workspace_proximity/perception/laser_scan.hpp"
#include "workspace_proximity/perception/self_filter.hpp"
#include "workspace_proximity/perception/voxel_clusters.hpp"
#include "workspace_proximity/perception/voxel_grid.hpp"

namespace workspace_proximity {
namespace perception {

struct CloudFrameParams {
  Aabb volume{Eigen::Vector3d(-2.0, -2.0, 0.0), Eigen::Vector3d(2.0, 2.0, 2.5)};  ///< m, fixed frame
  double voxel_size = 0.05;       ///< m
  double floor_height = 0.0;      ///< m, fixed frame z of the floor
  double floor_tolerance = 0.03;  ///< m: points below floor_height + this are floor
  double self_padding = 0.03;     ///< m around every robot link
  double near_band = 0.05;        ///< m outside the padded robot: the health count's band
  int min_cluster_points = 3;     ///< smaller clusters are noise
  std::int64_t max_points = 4000000;  ///< larger clouds are refused (kTooManyPoints)
  std::int64_t max_cells = 4000000;   ///< largest grid (volume / voxel_size^3)
  int max_clusters = 512;
  int max_links = 64;
  std::int64_t max_scan_points = 400000;  ///< beams x band layers of one scan (processScan)
};

/// "" when the parameters are usable, else a message naming the first bad one.
std::string checkCloudFrameParams(const CloudFrameParams& params);

/// Monitored volume by default: a box around the robot's base reaching `robot_reach` +
/// `ssm_reach` (R) on every side, cut at the floor (m, fixed frame).
Aabb defaultMonitoredVolume(const Eigen::Vector3d& base, double robot_reach, double ssm_reach,
                            double floor_height);
/// m: how far the robot's links reach from `base`: the largest |link origin - base| + the
/// link shape's bounding radius (links as posed now; use the links' extreme poses, or a
/// URDF's full reach, for a volume that holds every pose).
double robotReach(const SelfLink* links, int count, const Eigen::Vector3d& base);

/// What one frame did with its points (each point is counted in exactly one of the last six).
struct CloudFrameStats {
  CloudRejection rejected = CloudRejection::kNone;
  std::int64_t points_in = 0;
  std::int64_t non_finite = 0;      ///< NaN or inf coordinates: dropped
  std::int64_t outside_volume = 0;  ///< cropped
  std::int64_t floor = 0;           ///< below floor_height + floor_tolerance
  std::int64_t self = 0;            ///< inside the grown robot
  std::int64_t near_robot = 0;      ///< kept, but within near_band of the grown robot
  std::int64_t kept = 0;            ///< kept, farther out (near_robot + kept are voxelized)
  std::int64_t voxels = 0;          ///< occupied cells
  int clusters = 0;                 ///< detections reported
  int clusters_small = 0;           ///< dropped as smaller than min_cluster_points
  int clusters_overflow = 0;        ///< beyond max_clusters: not reported
};

class CloudFrame {
 public:
  /// Throws std::invalid_argument naming the parameter when checkCloudFrameParams refuses.
  explicit CloudFrame(const CloudFrameParams& params);

  const CloudFrameParams& params() const { return params_; }

  /// The robot for the next process() calls: its links at the pose stamp and the cloud
  /// stamp's offset from it (s). False when the self-filter refuses them (then no point is
  /// filtered as the robot's; the caller reports the robot unknown).
  bool setRobot(const SelfLink* links, int count, double stamp_offset);
  /// No robot links (nothing self-filtered).
  void clearRobot();

  /// One cloud; `sensor_to_fixed` maps its points into the fixed frame, its translation is
  /// the sensor's origin (for shadows cast from outside the volume). Returns the stats;
  /// detections() and grid() hold the frame until the next call.
  const CloudFrameStats& process(const CloudView& cloud, const Eigen::Isometry3f& sensor_to_fixed);

  /// One laser scan: each valid beam a column over `band` (scanToPoints), then as process().
  /// A beam whose hit, in the scan plane, lies inside the grown robot is the robot's: its
  /// whole column is dropped (counted in `self`), so a scanner that sees the robot's base
  /// does not make a column above it. A refused band or header counts as kBadLayout; beams
  /// beyond max_scan_points are dropped and counted in scanResult().truncated.
  const CloudFrameStats& processScan(const ScanView& scan, const ScanBand& band,
                                     const Eigen::Isometry3f& scan_to_fixed);
  const ScanResult& scanResult() const { return scan_result_; }

  const CloudFrameStats& stats() const { return stats_; }
  const std::vector<Detection>& detections() const { return clusters_.detections(); }
  const VoxelGrid& grid() const { return grid_; }
  const SelfFilter& selfFilter() const { return self_; }

 private:
  void shadowFromOutside(const Eigen::Vector3f& origin, const Eigen::Vector3f& p);

  CloudFrameParams params_;
  VoxelGrid grid_;
  VoxelClusters clusters_;
  SelfFilter self_;
  CloudFrameStats stats_;
  ScanResult scan_result_;
  std::vector<float> scan_xyz_;  // capacity max_scan_points
  Eigen::Vector3f lower_, upper_;  // the volume, float
  float floor_z_ = 0.0f;
};

}  // namespace perception
}  // namespace workspace_proximity

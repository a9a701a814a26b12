#pragma once
/// The peers of bench/perception_bench.cpp (issue 23), each in its own translation unit so
/// that PCL's and octomap's headers stay out of the benchmark's main file and out of every
/// build without them. Plain arrays in, counts and stage times out.

#include <cstdint>

namespace perception_peers {

/// One organised depth frame as the sensor gives it: packed float x, y, z per pixel (NaN for
/// no return), in the sensor frame.
struct Frame {
  const float* xyz = nullptr;
  int width = 0;
  int height = 0;
  float sensor_to_fixed[16] = {};  ///< column-major 4 x 4, the sensor's pose in the fixed frame
};

/// The monitored volume and the settings ours uses (m, fixed frame).
struct Settings {
  float lower[3] = {0, 0, 0};
  float upper[3] = {0, 0, 0};
  float floor_cut = 0.03f;          ///< points below are floor (ours: floor_height + tolerance)
  float voxel = 0.05f;              ///< voxel edge
  float cluster_tolerance = 0.0866f;  ///< PCL's Euclidean tolerance between voxel centroids
  int min_cluster_size = 1;         ///< PCL: voxel centroids per cluster
  float max_range = 6.0f;           ///< octomap: beams cut at this range
};

/// What one frame took, by stage (ms), and what came out.
struct Result {
  double total_ms = 0;
  double stage_ms[4] = {0, 0, 0, 0};  ///< per peer: see its stage names
  std::int64_t points = 0;            ///< points after the crop
  std::int64_t voxels = 0;            ///< PCL: voxel centroids; octomap: leaves in the tree
  int clusters = 0;
};

#ifdef WP_BENCH_PCL
/// PCL 1.13 as its users run it: pcl::transformPointCloud, pcl::CropBox (volume, above the
/// floor; drops NaNs), pcl::VoxelGrid, pcl::EuclideanClusterExtraction with a
/// pcl::search::KdTree. Stages: transform, crop, voxel grid, clusters (tree build included).
/// The cloud is held as pcl::PointCloud<pcl::PointXYZ> from the start (no conversion timed).
class PclPeer {
 public:
  PclPeer(const Frame& frame, const Settings& settings);
  ~PclPeer();
  Result run();
  static const char* const kStages[4];

 private:
  struct Impl;
  Impl* impl_;
};
#endif

#ifdef WP_BENCH_OCTOMAP
/// octomap 1.9 as octomap_server and MoveIt's occupancy map use it: one persistent
/// octomap::OcTree at the voxel size, each frame's points (NaN-free, in the fixed frame)
/// inserted with OcTree::insertPointCloud from the sensor origin up to max_range (free cells
/// along every ray, occupied at its end). Stages: points to an octomap::Pointcloud
/// (transform, NaNs, crop), insertPointCloud.
class OctomapPeer {
 public:
  /// crop: the points are cropped to the volume first (as ours and PCL are); else the whole
  /// NaN-free frame goes in (octomap_server's default, no bounding box).
  OctomapPeer(const Frame& frame, const Settings& settings, bool crop);
  ~OctomapPeer();
  Result run();
  static const char* const kStages[2];

 private:
  struct Impl;
  Impl* impl_;
};
#endif

}  // namespace perception_peers

#pragma once
/// Connected voxel clusters: the occupied cells of one frame's VoxelGrid (cells with object
/// points) joined through faces, edges and corners (26-neighbourhood), each turned into a
/// detection: an axis-aligned box around its cells. Breadth-first search over flat arrays;
/// ROS-free; allocation-free after configure().

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "workspace_proximity/perception/voxel_grid.hpp"

namespace workspace_proximity {
namespace perception {

/// One cluster, fixed frame.
struct Detection {
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();  ///< m, centre of the box
  Eigen::Vector3f size = Eigen::Vector3f::Zero();    ///< m, full dimensions (whole voxels)
  std::int32_t points = 0;                           ///< object points in it
  std::int32_t voxels = 0;                           ///< occupied cells in it
};

class VoxelClusters {
 public:
  /// At most `max_clusters` detections a frame.
  explicit VoxelClusters(int max_clusters);

  /// Sizes the work arrays for `grid` (allocates; call after grid.configure()).
  void configure(const VoxelGrid& grid);

  /// Clusters this frame's occupied cells. A cluster with fewer than `min_points` points is
  /// counted in dropped_small(); beyond max_clusters, clusters are counted in overflow() and
  /// not reported (the caller must not read the frame as complete then). Returns the
  /// detections (valid until the next build()).
  const std::vector<Detection>& build(const VoxelGrid& grid, int min_points);

  const std::vector<Detection>& detections() const { return detections_; }
  int droppedSmall() const { return dropped_small_; }
  int overflow() const { return overflow_; }

 private:
  int max_clusters_;
  std::vector<std::int32_t> label_;   // per cell: -1, or the cluster being built / built
  std::vector<std::int64_t> queue_;   // cells of the search; capacity every cell
  std::vector<Detection> detections_;
  int dropped_small_ = 0;
  int overflow_ = 0;
};

}  // namespace perception
}  // namespace workspace_proximity

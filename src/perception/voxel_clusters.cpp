#include "workspace_proximity/perception/voxel_clusters.hpp"

#include <algorithm>

namespace workspace_proximity {
namespace perception {

VoxelClusters::VoxelClusters(int max_clusters) : max_clusters_(std::max(0, max_clusters)) {
  detections_.reserve(static_cast<std::size_t>(max_clusters_));
}

void VoxelClusters::configure(const VoxelGrid& grid) {
  label_.assign(static_cast<std::size_t>(grid.cells()), -1);
  queue_.clear();
  queue_.reserve(static_cast<std::size_t>(grid.cells()));
}

const std::vector<Detection>& VoxelClusters::build(const VoxelGrid& grid, int min_points) {
  detections_.clear();
  dropped_small_ = 0;
  overflow_ = 0;
  const std::int64_t nx = grid.nx(), ny = grid.ny(), nz = grid.nz();
  const float size = grid.voxelSize();
  const auto& touched = grid.touched();
  int cluster = 0;
  for (const std::int64_t seed : touched) {
    if (grid.count(seed) == 0 || label_[static_cast<std::size_t>(seed)] >= 0) continue;
    // Breadth-first over the 26 neighbours; the queue doubles as the cluster's cell list.
    queue_.clear();
    queue_.push_back(seed);
    label_[static_cast<std::size_t>(seed)] = cluster;
    Eigen::Matrix<std::int64_t, 3, 1> lo = grid.coords(seed), hi = lo;
    std::int64_t points = 0;
    for (std::size_t head = 0; head < queue_.size(); ++head) {
      const std::int64_t cell = queue_[head];
      points += grid.count(cell);
      const auto c = grid.coords(cell);
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
      for (std::int64_t dz = -1; dz <= 1; ++dz) {
        const std::int64_t z = c.z() + dz;
        if (z < 0 || z >= nz) continue;
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const std::int64_t y = c.y() + dy;
          if (y < 0 || y >= ny) continue;
          for (std::int64_t dx = -1; dx <= 1; ++dx) {
            const std::int64_t x = c.x() + dx;
            if (x < 0 || x >= nx) continue;
            const std::int64_t n = grid.cellAt(x, y, z);
            if (grid.count(n) == 0 || label_[static_cast<std::size_t>(n)] >= 0) continue;
            label_[static_cast<std::size_t>(n)] = cluster;
            queue_.push_back(n);
          }
        }
      }
    }
    ++cluster;
    if (points < min_points) {
      ++dropped_small_;
      continue;
    }
    if (static_cast<int>(detections_.size()) >= max_clusters_) {
      ++overflow_;
      continue;
    }
    Detection d;
    const Eigen::Vector3f lower = grid.origin() + lo.cast<float>() * size;
    const Eigen::Vector3f upper = grid.origin() + (hi.cast<float>() + Eigen::Vector3f::Ones()) * size;
    d.centre = 0.5f * (lower + upper);
    d.size = upper - lower;
    d.points = static_cast<std::int32_t>(std::min<std::int64_t>(points, INT32_MAX));
    d.voxels = static_cast<std::int32_t>(queue_.size());
    detections_.push_back(d);
  }
  // No memory between frames: the labels go back to -1 for the cells this frame used.
  for (const std::int64_t c : touched) label_[static_cast<std::size_t>(c)] = -1;
  return detections_;
}

}  // namespace perception
}  // namespace workspace_proximity

#pragma once
/// The unseen voxels of the protective volume as a few boxes (issue 23, `~unseen: occupied`),
/// ROS-free: neighbouring cells merged greedily into axis-aligned boxes (runs along x, then
/// whole rows along y, then whole slabs along z), so that the monitor gets tens of boxes, not
/// thousands of voxels. The boxes cover exactly the given cells, and never overlap; beyond
/// `max_boxes` the cells left are covered by their one bounding box (more than unseen, never
/// less: unseen is never clear). Allocation-free after configure().

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "workspace_proximity/perception/voxel_grid.hpp"

namespace workspace_proximity {
namespace perception {

struct CellBox {
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();  ///< m, fixed frame
  Eigen::Vector3f size = Eigen::Vector3f::Zero();    ///< m, full edges (whole voxels)
  std::int32_t cells = 0;  ///< cells it holds (its volume in voxels, but for the last box
                           ///< beyond max_boxes, which may hold fewer than its volume)
};

class UnseenBoxes {
 public:
  /// `max_boxes` >= 1 (smaller: 1).
  explicit UnseenBoxes(int max_boxes = 64) : max_boxes_(max_boxes < 1 ? 1 : max_boxes) {
    boxes_.reserve(static_cast<std::size_t>(max_boxes_));
  }
  /// Sizes the work arrays for `grid` (allocates).
  void configure(const VoxelGrid& grid);
  /// Boxes covering `cells` (cell indices of `grid`, no duplicates), valid until the next call.
  const std::vector<CellBox>& build(const VoxelGrid& grid, const std::vector<std::int64_t>& cells);
  const std::vector<CellBox>& boxes() const { return boxes_; }
  /// Whether the last build() ran out of boxes (its last box bounds the rest).
  bool capped() const { return capped_; }

 private:
  int max_boxes_;
  std::vector<std::uint8_t> mark_;    // per cell: 1 while unseen and not yet in a box
  std::vector<std::int64_t> sorted_;  // the cells, in index order
  std::vector<CellBox> boxes_;
  bool capped_ = false;
};

}  // namespace perception
}  // namespace workspace_proximity

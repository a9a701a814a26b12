#pragma once
/// One frame's voxels: a dense grid over the monitored volume (an axis-aligned box), with per
/// cell a point count (object points: after crop, floor and self-filter) and flags (any
/// point at all; a shadow cast from outside the volume). No memory between frames: clear()
/// resets exactly the cells the last frame touched. ROS-free; allocation-free after
/// configure().

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "workspace_proximity/aabb.hpp"

namespace workspace_proximity {
namespace perception {

class VoxelGrid {
 public:
  /// Cell flags.
  static constexpr std::uint8_t kHit = 1;     ///< a point (any: floor, robot, object) fell in it
  static constexpr std::uint8_t kShadow = 2;  ///< a point outside the volume, between it and
                                              ///< the sensor, blocks the rays entering here

  /// `max_cells`: the largest grid configure() accepts (memory: about 11 bytes a cell).
  explicit VoxelGrid(std::int64_t max_cells);

  /// A grid of cubes of `voxel_size` m from volume.lower, covering the volume (the last cells
  /// may reach past volume.upper). False, with `why` naming the problem, for an invalid or
  /// empty volume, a non-positive size or more than max_cells cells; the grid is then empty.
  bool configure(const Aabb& volume, double voxel_size, std::string* why);

  /// Resets the cells the last frame touched.
  void clear();

  /// The cell holding `p` (fixed frame), or -1 outside the grid.
  std::int64_t cellOf(const Eigen::Vector3f& p) const {
    const Eigen::Vector3f q = (p - origin_) * inv_size_;
    // Negated comparisons: NaN is outside; compared in float before any conversion, so a huge
    // coordinate never reaches the (then undefined) float-to-integer cast.
    if (!(q.x() >= 0.0f && q.y() >= 0.0f && q.z() >= 0.0f && q.x() < n_f_.x() &&
          q.y() < n_f_.y() && q.z() < n_f_.z())) {
      return -1;
    }
    const auto ix = static_cast<std::int64_t>(q.x());
    const auto iy = static_cast<std::int64_t>(q.y());
    const auto iz = static_cast<std::int64_t>(q.z());
    if (ix >= nx_ || iy >= ny_ || iz >= nz_) return -1;
    return (iz * ny_ + iy) * nx_ + ix;
  }
  std::int64_t cellAt(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
    return (iz * ny_ + iy) * nx_ + ix;
  }

  /// An object point in `cell` (also a hit).
  void addPoint(std::int64_t cell) {
    touch(cell);
    flags_[static_cast<std::size_t>(cell)] |= kHit;
    auto& c = counts_[static_cast<std::size_t>(cell)];
    if (c != 0xffff) ++c;  // saturates: a count is a size, not an identity
  }
  /// A point that is no object (floor, robot) in `cell`: it still blocks the view.
  void addHit(std::int64_t cell) {
    touch(cell);
    flags_[static_cast<std::size_t>(cell)] |= kHit;
  }
  void addShadow(std::int64_t cell) {
    touch(cell);
    flags_[static_cast<std::size_t>(cell)] |= kShadow;
  }

  std::uint16_t count(std::int64_t cell) const { return counts_[static_cast<std::size_t>(cell)]; }
  std::uint8_t flags(std::int64_t cell) const { return flags_[static_cast<std::size_t>(cell)]; }
  /// Every cell's flags, by cell index.
  const std::uint8_t* flagData() const { return flags_.data(); }
  /// Cells with a count or a flag this frame, in the order first touched.
  const std::vector<std::int64_t>& touched() const { return touched_; }
  /// Cells with an object point this frame.
  std::int64_t occupiedCount() const;

  std::int64_t nx() const { return nx_; }
  std::int64_t ny() const { return ny_; }
  std::int64_t nz() const { return nz_; }
  std::int64_t cells() const { return nx_ * ny_ * nz_; }
  float voxelSize() const { return size_; }
  const Eigen::Vector3f& origin() const { return origin_; }
  /// The grid's box (lower = origin, upper = origin + n x size).
  Aabb box() const;
  /// Integer coordinates of a cell.
  Eigen::Matrix<std::int64_t, 3, 1> coords(std::int64_t cell) const {
    return {cell % nx_, (cell / nx_) % ny_, cell / (nx_ * ny_)};
  }
  /// Centre of a cell, fixed frame.
  Eigen::Vector3f centre(std::int64_t cell) const;

 private:
  void touch(std::int64_t cell) {
    const auto c = static_cast<std::size_t>(cell);
    if (counts_[c] == 0 && flags_[c] == 0) touched_.push_back(cell);
  }

  std::int64_t max_cells_;
  std::int64_t nx_ = 0, ny_ = 0, nz_ = 0;
  float size_ = 0.0f, inv_size_ = 0.0f;
  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  Eigen::Vector3f n_f_ = Eigen::Vector3f::Zero();  // nx, ny, nz as floats
  std::vector<std::uint16_t> counts_;
  std::vector<std::uint8_t> flags_;
  std::vector<std::int64_t> touched_;  // capacity: every cell
};

}  // namespace perception
}  // namespace workspace_proximity

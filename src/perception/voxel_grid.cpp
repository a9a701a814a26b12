#include "workspace_proximity/perception/voxel_grid.hpp"

#include <cmath>

namespace workspace_proximity {
namespace perception {

VoxelGrid::VoxelGrid(std::int64_t max_cells) : max_cells_(max_cells) {}

bool VoxelGrid::configure(const Aabb& volume, double voxel_size, std::string* why) {
  nx_ = ny_ = nz_ = 0;
  n_f_.setZero();
  touched_.clear();
  auto fail = [&](const std::string& text) {
    if (why != nullptr) *why = text;
    return false;
  };
  if (!volume.valid()) return fail("volume: not finite or lower > upper");
  if (!std::isfinite(voxel_size) || voxel_size <= 0.0) return fail("voxel_size: must be > 0");
  const Eigen::Vector3d extent = volume.upper - volume.lower;
  double n[3];
  for (int k = 0; k < 3; ++k) {
    n[k] = std::max(1.0, std::ceil(extent[k] / voxel_size - 1e-9));
  }
  if (n[0] * n[1] * n[2] > static_cast<double>(max_cells_)) {
    return fail("volume / voxel_size^3: " + std::to_string(static_cast<long long>(n[0] * n[1] * n[2])) +
                " cells, more than max_cells " + std::to_string(static_cast<long long>(max_cells_)));
  }
  nx_ = static_cast<std::int64_t>(n[0]);
  ny_ = static_cast<std::int64_t>(n[1]);
  nz_ = static_cast<std::int64_t>(n[2]);
  size_ = static_cast<float>(voxel_size);
  inv_size_ = static_cast<float>(1.0 / voxel_size);
  origin_ = volume.lower.cast<float>();
  n_f_ = Eigen::Vector3f(static_cast<float>(nx_), static_cast<float>(ny_), static_cast<float>(nz_));
  const auto total = static_cast<std::size_t>(cells());
  counts_.assign(total, 0);
  flags_.assign(total, 0);
  touched_.reserve(total);
  return true;
}

void VoxelGrid::clear() {
  for (const std::int64_t c : touched_) {
    counts_[static_cast<std::size_t>(c)] = 0;
    flags_[static_cast<std::size_t>(c)] = 0;
  }
  touched_.clear();
}

std::int64_t VoxelGrid::occupiedCount() const {
  std::int64_t n = 0;
  for (const std::int64_t c : touched_) n += counts_[static_cast<std::size_t>(c)] != 0 ? 1 : 0;
  return n;
}

Aabb VoxelGrid::box() const {
  const Eigen::Vector3d lo = origin_.cast<double>();
  const Eigen::Vector3d n(static_cast<double>(nx_), static_cast<double>(ny_), static_cast<double>(nz_));
  return Aabb{lo, lo + n * static_cast<double>(size_)};
}

Eigen::Vector3f VoxelGrid::centre(std::int64_t cell) const {
  const auto c = coords(cell);
  return origin_ + (c.cast<float>() + Eigen::Vector3f::Constant(0.5f)) * size_;
}

}  // namespace perception
}  // namespace workspace_proximity

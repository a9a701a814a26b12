#include "workspace_proximity/perception/unseen_boxes.hpp"

#include <algorithm>

namespace workspace_proximity {
namespace perception {

void UnseenBoxes::configure(const VoxelGrid& grid) {
  mark_.assign(static_cast<std::size_t>(grid.cells()), 0);
  sorted_.reserve(static_cast<std::size_t>(grid.cells()));
}

const std::vector<CellBox>& UnseenBoxes::build(const VoxelGrid& grid, const std::vector<std::int64_t>& cells) {
  boxes_.clear();
  capped_ = false;
  sorted_.assign(cells.begin(), cells.end());
  std::sort(sorted_.begin(), sorted_.end());
  for (std::int64_t c : sorted_) mark_[static_cast<std::size_t>(c)] = 1;
  const std::int64_t nx = grid.nx(), ny = grid.ny(), nz = grid.nz();
  const float size = grid.voxelSize();
  auto marked = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return mark_[static_cast<std::size_t>(grid.cellAt(x, y, z))] != 0;
  };
  auto emit = [&](const Eigen::Matrix<std::int64_t, 3, 1>& lo, const Eigen::Matrix<std::int64_t, 3, 1>& hi,
                  std::int32_t count) {
    CellBox& b = boxes_.emplace_back();
    const Eigen::Vector3f lower = grid.origin() + size * lo.cast<float>();
    const Eigen::Vector3f upper = grid.origin() + size * (hi.cast<float>() + Eigen::Vector3f::Ones());
    b.centre = 0.5f * (lower + upper);
    b.size = upper - lower;
    b.cells = count;
  };
  for (std::size_t i = 0; i < sorted_.size(); ++i) {
    const std::int64_t start = sorted_[i];
    if (mark_[static_cast<std::size_t>(start)] == 0) continue;  // in a box already
    const Eigen::Matrix<std::int64_t, 3, 1> lo = grid.coords(start);
    if (static_cast<int>(boxes_.size()) == max_boxes_ - 1) {
      // The last box bounds every cell left, so none goes uncovered.
      Eigen::Matrix<std::int64_t, 3, 1> a = lo, b = lo;
      std::int32_t count = 0;
      for (std::size_t j = i; j < sorted_.size(); ++j) {
        const std::int64_t c = sorted_[j];
        if (mark_[static_cast<std::size_t>(c)] == 0) continue;
        mark_[static_cast<std::size_t>(c)] = 0;
        const Eigen::Matrix<std::int64_t, 3, 1> k = grid.coords(c);
        a = a.cwiseMin(k);
        b = b.cwiseMax(k);
        ++count;
      }
      emit(a, b, count);
      capped_ = true;
      break;
    }
    // Cells are visited in index order (x fastest): `start` is the lowest corner of its box.
    std::int64_t x1 = lo.x();
    while (x1 + 1 < nx && marked(x1 + 1, lo.y(), lo.z())) ++x1;
    auto row = [&](std::int64_t y, std::int64_t z) {
      for (std::int64_t x = lo.x(); x <= x1; ++x) {
        if (!marked(x, y, z)) return false;
      }
      return true;
    };
    std::int64_t y1 = lo.y();
    while (y1 + 1 < ny && row(y1 + 1, lo.z())) ++y1;
    auto slab = [&](std::int64_t z) {
      for (std::int64_t y = lo.y(); y <= y1; ++y) {
        if (!row(y, z)) return false;
      }
      return true;
    };
    std::int64_t z1 = lo.z();
    while (z1 + 1 < nz && slab(z1 + 1)) ++z1;
    for (std::int64_t z = lo.z(); z <= z1; ++z) {
      for (std::int64_t y = lo.y(); y <= y1; ++y) {
        for (std::int64_t x = lo.x(); x <= x1; ++x) mark_[static_cast<std::size_t>(grid.cellAt(x, y, z))] = 0;
      }
    }
    emit(lo, Eigen::Matrix<std::int64_t, 3, 1>(x1, y1, z1),
         static_cast<std::int32_t>((x1 - lo.x() + 1) * (y1 - lo.y() + 1) * (z1 - lo.z() + 1)));
  }
  return boxes_;
}

}  // namespace perception
}  // namespace workspace_proximity

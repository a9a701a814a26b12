#include "workspace_proximity/perception/unseen_share.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace workspace_proximity {
namespace perception {

UnseenShare::UnseenShare(int max_sensors) : max_sensors_(std::max(0, max_sensors)) {
  to_sensor_.resize(static_cast<std::size_t>(max_sensors_));
}

void UnseenShare::configure(const VoxelGrid& geometry) {
  const Aabb box = geometry.box();
  geometry_ = VoxelGrid(geometry.cells());
  geometry_.configure(box, geometry.voxelSize(), nullptr);
  const auto cells = static_cast<std::size_t>(geometry.cells());
  mark_.assign(cells, 0);
  marked_.clear();
  marked_.reserve(cells);
  protective_.clear();
  protective_.reserve(cells);
  unseen_cells_.clear();
  unseen_cells_.reserve(cells);
}

bool UnseenShare::inView(const SensorFov& fov, const Eigen::Vector3d& p) {
  const Eigen::Vector3d v = fov.pose.inverse(Eigen::Isometry) * p;
  const double range = v.norm();
  if (!(range >= fov.range_min && range <= fov.range_max)) return false;
  const double azimuth = std::atan2(v.y(), v.x());
  const double elevation = std::atan2(v.z(), std::hypot(v.x(), v.y()));
  return azimuth >= fov.azimuth_min && azimuth <= fov.azimuth_max &&
         elevation >= fov.elevation_min && elevation <= fov.elevation_max;
}

bool UnseenShare::blocked(const VoxelGrid& grid, const Eigen::Vector3d& from, std::int64_t cell) {
  // Amanatides & Woo's voxel walk, in voxel units, from the cell's centre towards `from`: every
  // voxel the segment passes through, in order, until it reaches `from`'s voxel or leaves the
  // grid (nothing outside is known; shadows from outside sit in the entry voxels).
  if ((grid.flags(cell) & VoxelGrid::kHit) != 0) return false;  // a surface measured here
  if ((grid.flags(cell) & VoxelGrid::kShadow) != 0) return true;
  const double size = grid.voxelSize();
  const Eigen::Vector3d origin = grid.origin().cast<double>();
  const Eigen::Matrix<std::int64_t, 3, 1> c = grid.coords(cell);
  const Eigen::Vector3d start = c.cast<double>() + Eigen::Vector3d::Constant(0.5);
  const Eigen::Vector3d end = (from - origin) / size;
  const Eigen::Vector3d dir = end - start;
  const std::int64_t n[3] = {grid.nx(), grid.ny(), grid.nz()};
  std::int64_t i[3] = {c.x(), c.y(), c.z()};
  std::int64_t last[3], step[3];
  double t_max[3], t_delta[3];
  const double inf = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    last[k] = static_cast<std::int64_t>(std::floor(end[k]));
    step[k] = dir[k] > 0.0 ? 1 : (dir[k] < 0.0 ? -1 : 0);
    if (step[k] == 0) {
      t_max[k] = t_delta[k] = inf;
    } else {
      const double boundary = step[k] > 0 ? static_cast<double>(i[k] + 1) : static_cast<double>(i[k]);
      t_max[k] = (boundary - start[k]) / dir[k];
      t_delta[k] = 1.0 / std::abs(dir[k]);
    }
  }
  for (;;) {
    int axis = 0;
    if (t_max[1] < t_max[axis]) axis = 1;
    if (t_max[2] < t_max[axis]) axis = 2;
    if (t_max[axis] > 1.0) return false;  // reached `from`'s voxel
    i[axis] += step[axis];
    t_max[axis] += t_delta[axis];
    if (i[axis] < 0 || i[axis] >= n[axis]) return false;  // left the grid
    if (i[0] == last[0] && i[1] == last[1] && i[2] == last[2]) return false;
    if (grid.flags(grid.cellAt(i[0], i[1], i[2])) != 0) return true;
  }
}

const UnseenResult& UnseenShare::compute(const SelfLink* links, int link_count, double reach,
                                         double padding, double floor_z,
                                         const SensorSight* sensors, int sensor_count) {
  result_ = UnseenResult{};
  for (const std::int64_t c : marked_) mark_[static_cast<std::size_t>(c)] = 0;
  marked_.clear();
  protective_.clear();
  unseen_cells_.clear();
  const VoxelGrid& g = geometry_;
  if (g.cells() == 0 || !(reach >= 0.0) || !(padding >= 0.0)) return result_;
  const double size = g.voxelSize();
  const Eigen::Vector3d origin = g.origin().cast<double>();

  // 1. Cells within reach of a link (1) and inside a padded link (2), link by link over the
  //    link's bounds grown by the reach.
  for (int l = 0; l < link_count; ++l) {
    const SelfLink& link = links[l];
    const Eigen::Vector3d half = link.pose.linear().cwiseAbs() * link.shape.localHalfExtents() +
                                 Eigen::Vector3d::Constant(reach + size);
    const Eigen::Vector3d lo = (link.pose.translation() - half - origin) / size;
    const Eigen::Vector3d hi = (link.pose.translation() + half - origin) / size;
    std::int64_t a[3], b[3];
    const std::int64_t n[3] = {g.nx(), g.ny(), g.nz()};
    for (int k = 0; k < 3; ++k) {
      a[k] = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor(lo[k])));
      b[k] = std::min<std::int64_t>(n[k] - 1, static_cast<std::int64_t>(std::floor(hi[k])));
    }
    const Eigen::Isometry3d to_link = link.pose.inverse(Eigen::Isometry);
    for (std::int64_t z = a[2]; z <= b[2]; ++z) {
      for (std::int64_t y = a[1]; y <= b[1]; ++y) {
        for (std::int64_t x = a[0]; x <= b[0]; ++x) {
          const Eigen::Vector3d centre =
              origin + (Eigen::Vector3d(x, y, z) + Eigen::Vector3d::Constant(0.5)) * size;
          const double d = shapeDistance(link.shape, Eigen::Vector3d(to_link * centre));
          if (d > reach) continue;
          const std::int64_t cell = g.cellAt(x, y, z);
          auto& m = mark_[static_cast<std::size_t>(cell)];
          if (m == 0) marked_.push_back(cell);
          m |= d <= padding ? 3 : 1;
        }
      }
    }
  }
  for (const std::int64_t cell : marked_) {
    if (mark_[static_cast<std::size_t>(cell)] != 1) continue;  // inside the padded robot
    if (static_cast<double>(g.centre(cell).z()) < floor_z) continue;
    protective_.push_back(cell);
  }

  // 2. Each protective cell against each sensor: in view, and not blocked in its frame.
  const int sensors_used = std::min(std::max(sensor_count, 0), max_sensors_);
  for (const std::int64_t cell : protective_) {
    const Eigen::Vector3d centre = g.centre(cell).cast<double>();
    bool seen = false, in_any_view = false;
    for (int s = 0; s < sensors_used && !seen; ++s) {
      const SensorSight& sight = sensors[s];
      if (sight.grid == nullptr || sight.grid->cells() != g.cells()) continue;
      if (!inView(sight.fov, centre)) continue;
      in_any_view = true;
      seen = !blocked(*sight.grid, sight.fov.pose.translation(), cell);
    }
    if (seen) continue;
    ++result_.unseen;
    ++(in_any_view ? result_.shadowed : result_.outside_fov);
    unseen_cells_.push_back(cell);
  }
  result_.protective = static_cast<std::int64_t>(protective_.size());
  result_.share = result_.protective > 0
                      ? static_cast<double>(result_.unseen) / static_cast<double>(result_.protective)
                      : 0.0;
  return result_;
}

}  // namespace perception
}  // namespace workspace_proximity

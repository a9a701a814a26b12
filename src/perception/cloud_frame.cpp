#include "workspace_proximity/perception/cloud_frame.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace workspace_proximity {
namespace perception {

namespace {

bool finiteNonNegative(double v) { return std::isfinite(v) && v >= 0.0; }

float readFloat(const std::uint8_t* p) {
  float f;
  std::memcpy(&f, p, sizeof f);  // clouds need not be aligned
  return f;
}

}  // namespace

std::string checkCloudFrameParams(const CloudFrameParams& p) {
  if (!p.volume.valid()) return "volume: not finite, or lower above upper";
  if (!std::isfinite(p.voxel_size) || p.voxel_size < 0.005 || p.voxel_size > 1.0) {
    return "voxel_size: must be within [0.005, 1] m";
  }
  if (!std::isfinite(p.floor_height)) return "floor_height: not finite";
  if (!finiteNonNegative(p.floor_tolerance)) return "floor_tolerance: must be >= 0";
  if (!finiteNonNegative(p.self_padding)) return "self_padding: must be >= 0";
  if (!finiteNonNegative(p.near_band)) return "near_band: must be >= 0";
  if (p.min_cluster_points < 1) return "min_cluster_points: must be >= 1";
  if (p.max_points < 1) return "max_points: must be >= 1";
  if (p.max_cells < 1) return "max_cells: must be >= 1";
  if (p.max_clusters < 1) return "max_clusters: must be >= 1";
  if (p.max_links < 0) return "max_links: must be >= 0";
  if (p.max_scan_points < 1 || p.max_scan_points > 100000000) {
    return "max_scan_points: must be within [1, 1e8]";
  }
  const Eigen::Vector3d extent = p.volume.upper - p.volume.lower;
  double cells = 1.0;
  for (int k = 0; k < 3; ++k) cells *= std::max(1.0, std::ceil(extent[k] / p.voxel_size - 1e-9));
  if (cells > static_cast<double>(p.max_cells)) {
    return "volume / voxel_size^3: " + std::to_string(static_cast<long long>(cells)) +
           " cells, more than max_cells";
  }
  return "";
}

Aabb defaultMonitoredVolume(const Eigen::Vector3d& base, double robot_reach, double ssm_reach,
                            double floor_height) {
  const double r = robot_reach + ssm_reach;
  Aabb box{base - Eigen::Vector3d::Constant(r), base + Eigen::Vector3d::Constant(r)};
  box.lower.z() = std::max(box.lower.z(), floor_height);
  return box;
}

double robotReach(const SelfLink* links, int count, const Eigen::Vector3d& base) {
  double reach = 0.0;
  for (int i = 0; i < count; ++i) {
    reach = std::max(reach, (links[i].pose.translation() - base).norm() +
                                links[i].shape.boundingRadius());
  }
  return reach;
}

CloudFrame::CloudFrame(const CloudFrameParams& params)
    : params_(params),
      grid_(params.max_cells),
      clusters_(params.max_clusters),
      self_(params.max_links) {
  const std::string why = checkCloudFrameParams(params);
  if (!why.empty()) throw std::invalid_argument(why);
  std::string grid_why;
  if (!grid_.configure(params.volume, params.voxel_size, &grid_why)) {
    throw std::invalid_argument(grid_why);
  }
  clusters_.configure(grid_);
  scan_xyz_.resize(static_cast<std::size_t>(3 * params.max_scan_points));
  // The crop is the grid's box: the volume rounded out to whole voxels.
  const Aabb box = grid_.box();
  lower_ = box.lower.cast<float>();
  upper_ = box.upper.cast<float>();
  floor_z_ = static_cast<float>(params.floor_height + params.floor_tolerance);
}

bool CloudFrame::setRobot(const SelfLink* links, int count, double stamp_offset) {
  return self_.setLinks(links, count, params_.self_padding, stamp_offset, params_.near_band);
}

void CloudFrame::clearRobot() { self_.setLinks(nullptr, 0, 0.0, 0.0, 0.0); }

void CloudFrame::shadowFromOutside(const Eigen::Vector3f& origin, const Eigen::Vector3f& p) {
  // The ray origin + t (p - origin): where does it enter the grid's box? A point before the
  // entry (t_enter > 1) stands between the sensor and the volume and hides every cell the ray
  // meets inside; marking the entry cell as a shadow makes the visibility test see that.
  const Eigen::Vector3f d = p - origin;
  float t_enter = 0.0f, t_exit = 1e30f;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0f) {
      if (origin[k] < lower_[k] || origin[k] > upper_[k]) return;
      continue;
    }
    float t0 = (lower_[k] - origin[k]) / d[k];
    float t1 = (upper_[k] - origin[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    t_enter = std::max(t_enter, t0);
    t_exit = std::min(t_exit, t1);
  }
  if (t_enter <= 1.0f || t_enter > t_exit) return;  // behind the volume, or missing it
  // Half a voxel along the ray past the entry: inside the box, in the entry cell or the next.
  const float nudge = 0.5f * grid_.voxelSize() / d.norm();
  const std::int64_t cell = grid_.cellOf(origin + std::min(t_enter + nudge, t_exit) * d);
  if (cell >= 0) grid_.addShadow(cell);
}

const CloudFrameStats& CloudFrame::process(const CloudView& cloud,
                                           const Eigen::Isometry3f& sensor_to_fixed) {
  stats_ = CloudFrameStats{};
  grid_.clear();
  clusters_.build(grid_, params_.min_cluster_points);  // empties the detections
  stats_.rejected = checkCloud(cloud, params_.max_points);
  if (stats_.rejected != CloudRejection::kNone) return stats_;
  stats_.points_in = cloud.points();

  const Eigen::Matrix3f rot = sensor_to_fixed.linear();
  const Eigen::Vector3f origin = sensor_to_fixed.translation();
  const bool sensor_inside = (origin.array() >= lower_.array()).all() &&
                             (origin.array() <= upper_.array()).all();
  const Aabb& robot = self_.bounds();
  const bool has_robot = self_.count() > 0;
  const Eigen::Vector3f robot_lo = robot.lower.cast<float>(), robot_hi = robot.upper.cast<float>();

  for (std::int64_t row = 0; row < cloud.height; ++row) {
    const std::uint8_t* p = cloud.data + row * cloud.row_step;
    for (std::int64_t col = 0; col < cloud.width; ++col, p += cloud.point_step) {
      const Eigen::Vector3f local(readFloat(p + cloud.x_offset), readFloat(p + cloud.y_offset),
                                  readFloat(p + cloud.z_offset));
      if (!local.allFinite()) {
        ++stats_.non_finite;
        continue;
      }
      const Eigen::Vector3f q = rot * local + origin;
      const std::int64_t cell = grid_.cellOf(q);
      if (cell < 0) {
        ++stats_.outside_volume;
        if (!sensor_inside) shadowFromOutside(origin, q);
        continue;
      }
      if (q.z() < floor_z_) {
        ++stats_.floor;
        grid_.addHit(cell);  // the floor is not an object, but nothing is seen through it
        continue;
      }
      if (has_robot && (q.array() >= robot_lo.array()).all() && (q.array() <= robot_hi.array()).all()) {
        const SelfVerdict v = self_.classify(q);
        if (v == SelfVerdict::kSelf) {
          ++stats_.self;
          grid_.addHit(cell);  // the robot hides what is behind it
          continue;
        }
        if (v == SelfVerdict::kNear) {
          ++stats_.near_robot;
          grid_.addPoint(cell);
          continue;
        }
      }
      ++stats_.kept;
      grid_.addPoint(cell);
    }
  }
  stats_.voxels = grid_.occupiedCount();
  clusters_.build(grid_, params_.min_cluster_points);
  stats_.clusters = static_cast<int>(clusters_.detections().size());
  stats_.clusters_small = clusters_.droppedSmall();
  stats_.clusters_overflow = clusters_.overflow();
  return stats_;
}

const CloudFrameStats& CloudFrame::processScan(const ScanView& scan, const ScanBand& band,
                                               const Eigen::Isometry3f& scan_to_fixed) {
  scan_result_ = scanToPoints(scan, band, scan_xyz_.data(), params_.max_scan_points);
  if (scan_result_.refused) {
    stats_ = CloudFrameStats{};
    grid_.clear();
    clusters_.build(grid_, params_.min_cluster_points);
    stats_.rejected = CloudRejection::kBadLayout;
    return stats_;
  }
  // Columns whose beam hit the robot go; the others move up in place.
  const int layers = band.layers();
  const std::int64_t columns = scan_result_.points / layers;
  std::int64_t kept = 0, dropped = 0;
  for (std::int64_t c = 0; c < columns; ++c) {
    const float* col = scan_xyz_.data() + 3 * layers * c;
    const Eigen::Vector3f hit = scan_to_fixed * Eigen::Vector3f(col[0], col[1], 0.0f);
    if (self_.count() > 0 && self_.classify(hit) == SelfVerdict::kSelf) {
      dropped += layers;
      continue;
    }
    if (kept != c) {
      std::copy(col, col + 3 * layers, scan_xyz_.data() + 3 * layers * kept);
    }
    ++kept;
  }
  process(packedXyz(scan_xyz_.data(), kept * layers), scan_to_fixed);
  stats_.points_in += dropped;
  stats_.self += dropped;
  return stats_;
}

}  // namespace perception
}  // namespace workspace_proximity

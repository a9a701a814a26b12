#include "workspace_proximity/perception/unseen_share.hpp"

#include "shape_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace workspace_proximity {
namespace perception {

namespace {

// Angles and ranges of a point in a sensor's frame (fast, float), and the view test with the
// margins that make fastAtan2's error and float rounding conservative.
struct Bearing {
  float range, azimuth, elevation;
};

Bearing bearingOf(const Eigen::Vector3f& v) {
  const float planar = std::sqrt(v.x() * v.x() + v.y() * v.y());
  return {v.norm(), fastAtan2(v.y(), v.x()), fastAtan2(v.z(), planar)};
}

bool within(const SensorFov& fov, const Bearing& b) {
  constexpr float kRangeMargin = 1e-4f;  // m
  const float e = kFastAtan2Error;
  return b.range >= static_cast<float>(fov.range_min) + kRangeMargin &&
         b.range <= static_cast<float>(fov.range_max) - kRangeMargin &&
         b.azimuth >= static_cast<float>(fov.azimuth_min) + e &&
         b.azimuth <= static_cast<float>(fov.azimuth_max) - e &&
         b.elevation >= static_cast<float>(fov.elevation_min) + e &&
         b.elevation <= static_cast<float>(fov.elevation_max) - e;
}

}  // namespace

float fastAtan2(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  if (ax == 0.0f && ay == 0.0f) return 0.0f;
  const bool steep = ay > ax;
  const float z = steep ? ax / ay : ay / ax;  // in [0, 1]
  const float z2 = z * z;
  // A minimax polynomial for atan on [0, 1] (odd, in z^2).
  float a = z * (0.99997726f + z2 * (-0.33262347f + z2 * (0.19354346f + z2 * (-0.11643287f +
                 z2 * (0.05265332f + z2 * -0.01172120f)))));
  if (steep) a = static_cast<float>(M_PI / 2) - a;
  if (x < 0.0f) a = static_cast<float>(M_PI) - a;
  return y < 0.0f ? -a : a;
}

UnseenShare::UnseenShare(int max_sensors, std::int64_t max_bins, double bin_angle)
    : max_sensors_(std::max(0, max_sensors)),
      max_bins_(std::max<std::int64_t>(1, max_bins)),
      bin_angle_(bin_angle > 0.0 ? bin_angle : 0.004) {
  depth_.resize(static_cast<std::size_t>(max_bins_));
  inner_.resize(static_cast<std::size_t>(max_bins_));
}

std::int64_t UnseenShare::binOf(double azimuth, double elevation) const {
  const auto a = std::min<std::int64_t>(naz_ - 1, std::max<std::int64_t>(0, static_cast<std::int64_t>((azimuth - az0_) / bin_)));
  const auto e = std::min<std::int64_t>(nel_ - 1, std::max<std::int64_t>(0, static_cast<std::int64_t>((elevation - el0_) / bin_)));
  return e * naz_ + a;
}

void UnseenShare::fillDepth(const SensorSight& sight, const Eigen::Isometry3d& to_sensor) {
  const SensorFov& fov = sight.fov;
  const double span_az = std::max(fov.azimuth_max - fov.azimuth_min, 0.0);
  const double span_el = std::max(fov.elevation_max - fov.elevation_min, 0.0);
  bin_ = bin_angle_;
  // Coarser bins when the view needs more than the image holds (only more walks follow).
  while (std::ceil(span_az / bin_ + 1) * std::ceil(span_el / bin_ + 1) > static_cast<double>(max_bins_)) {
    bin_ *= 1.5;
  }
  az0_ = fov.azimuth_min;
  el0_ = fov.elevation_min;
  naz_ = static_cast<std::int64_t>(std::ceil(span_az / bin_)) + 1;
  nel_ = static_cast<std::int64_t>(std::ceil(span_el / bin_)) + 1;
  const float inf = std::numeric_limits<float>::infinity();
  std::fill(depth_.begin(), depth_.begin() + naz_ * nel_, inf);
  std::fill(inner_.begin(), inner_.begin() + naz_ * nel_, inf);
  all_near_ = false;
  const VoxelGrid& grid = *sight.grid;
  const Eigen::Matrix3f rot = to_sensor.linear().cast<float>();
  const Eigen::Vector3f shift = to_sensor.translation().cast<float>();
  // A line of sight crossing a voxel crosses its bounding sphere: the sphere's angular disc,
  // splatted over every bin it touches, at the sphere's nearest range.
  const double h = 0.5 * std::sqrt(3.0) * grid.voxelSize();
  const double two_pi = 2.0 * M_PI;
  for (const std::int64_t cell : grid.touched()) {
    if (grid.flags(cell) == 0) continue;
    const Bearing b = bearingOf(rot * grid.centre(cell) + shift);
    const double r = b.range;
    if (r <= h + 1e-3) {
      all_near_ = true;  // the sensor sits in this voxel's sphere: no bound from the image
      continue;
    }
    // Dilated by twice fastAtan2's error: the disc's centre and the target's direction are
    // each that far from the true ones at most.
    const double alpha = std::asin(h / r) + 2.0 * kFastAtan2Error;
    const double az = b.azimuth;
    const double el = b.elevation;
    const double el_lo = el - alpha, el_hi = el + alpha;
    const double pole = std::max(std::abs(el_lo), std::abs(el_hi));
    const double half_az = pole < M_PI / 2 - 1e-3 ? std::min(M_PI, alpha / std::cos(pole)) : M_PI;
    const auto e0 = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor((el_lo - el0_) / bin_)));
    const auto e1 = std::min<std::int64_t>(nel_ - 1, static_cast<std::int64_t>(std::floor((el_hi - el0_) / bin_)));
    if (e0 > e1) continue;
    const auto near = static_cast<float>(r - h - 1e-4);  // float rounding: never farther
    // The disc's azimuths, and the same shifted by a turn either way (views across +-pi).
    for (int turn = -1; turn <= 1; ++turn) {
      const double lo = az - half_az + turn * two_pi, hi = az + half_az + turn * two_pi;
      const auto a0 = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor((lo - az0_) / bin_)));
      const auto a1 = std::min<std::int64_t>(naz_ - 1, static_cast<std::int64_t>(std::floor((hi - az0_) / bin_)));
      for (std::int64_t e = e0; e <= e1; ++e) {
        float* row = depth_.data() + e * naz_;
        for (std::int64_t a = a0; a <= a1; ++a) row[a] = std::min(row[a], near);
      }
    }
    // The inscribed sphere (radius s/2, inside the voxel): every direction within beta of its
    // centre crosses it, so a line of sight in such a direction reaching beyond r + s/2 has
    // crossed the voxel. A bin counts when its centre is within beta - bin - 4 eps of the
    // sphere's centre: every point of a bin is within `bin` of its centre (a path along the
    // parallel and the meridian), and each of the two directions is within 2 eps of its
    // fastAtan2 estimate.
    const double beta = std::asin(0.5 * grid.voxelSize() / r);
    const double reach = beta - bin_ - 4.0 * kFastAtan2Error;
    if (reach <= 0.0 || std::abs(el) + reach >= M_PI / 2 - 1e-3) continue;
    const auto far = static_cast<float>(r + 0.5 * grid.voxelSize() + 1e-4);  // never nearer
    const double in_half_az = std::min(M_PI, reach / std::cos(std::abs(el) + reach));
    const auto f0 = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor((el - reach - el0_) / bin_)));
    const auto f1 = std::min<std::int64_t>(nel_ - 1, static_cast<std::int64_t>(std::floor((el + reach - el0_) / bin_)));
    const double sin_half_reach = std::sin(0.5 * reach);
    const double cos_el = std::cos(el);
    for (int turn = -1; turn <= 1; ++turn) {
      const double centre_az = az + turn * two_pi;
      const auto a0 = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor((centre_az - in_half_az - az0_) / bin_)));
      const auto a1 = std::min<std::int64_t>(naz_ - 1, static_cast<std::int64_t>(std::floor((centre_az + in_half_az - az0_) / bin_)));
      for (std::int64_t e = f0; e <= f1; ++e) {
        const double el_c = el0_ + (static_cast<double>(e) + 0.5) * bin_;
        const double s_el = std::sin(0.5 * (el_c - el));
        const double k = cos_el * std::cos(el_c);
        float* row = inner_.data() + e * naz_;
        for (std::int64_t a = a0; a <= a1; ++a) {
          const double az_c = az0_ + (static_cast<double>(a) + 0.5) * bin_;
          const double s_az = std::sin(0.5 * (az_c - centre_az));
          // Haversine: sin^2(d / 2) = sin^2(d_el / 2) + cos el cos el_c sin^2(d_az / 2).
          if (s_el * s_el + k * s_az * s_az <= sin_half_reach * sin_half_reach) {
            row[a] = std::min(row[a], far);
          }
        }
      }
    }
  }
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
  seen_.clear();
  seen_.reserve(cells);
}

bool UnseenShare::inView(const SensorFov& fov, const Eigen::Vector3d& p) {
  return within(fov, bearingOf((fov.pose.inverse(Eigen::Isometry) * p).cast<float>()));
}

bool UnseenShare::blocked(const VoxelGrid& grid, const Eigen::Vector3d& from, std::int64_t cell,
                          double until) {
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
  // The walk by cell index: one add per step instead of a product.
  const std::int64_t stride[3] = {1, n[0], n[0] * n[1]};
  const std::int64_t last_cell =
      (last[0] >= 0 && last[0] < n[0] && last[1] >= 0 && last[1] < n[1] && last[2] >= 0 && last[2] < n[2])
          ? grid.cellAt(last[0], last[1], last[2])
          : -1;
  const std::uint8_t* flags = grid.flagData();
  std::int64_t index = cell;
  for (;;) {
    int axis = 0;
    if (t_max[1] < t_max[axis]) axis = 1;
    if (t_max[2] < t_max[axis]) axis = 2;
    if (t_max[axis] > until) return false;  // reached `from`'s voxel, or nothing beyond
    i[axis] += step[axis];
    if (i[axis] < 0 || i[axis] >= n[axis]) return false;  // left the grid
    t_max[axis] += t_delta[axis];
    index += step[axis] * stride[axis];
    if (index == last_cell) return false;
    if (flags[index] != 0) return true;
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
  // Unknown is never clear: bad inputs give a refused result with the share 1.
  bool ok = g.cells() > 0 && std::isfinite(reach) && reach >= 0.0 && std::isfinite(padding) &&
            padding >= 0.0 && std::isfinite(floor_z) && link_count >= 0 &&
            (link_count == 0 || links != nullptr);
  for (int l = 0; ok && l < link_count; ++l) {
    ok = links[l].shape.valid() && links[l].pose.matrix().allFinite() &&
         links[l].pose.translation().cwiseAbs().maxCoeff() <= Limits::kMaxCoordinate;
  }
  if (!ok) {
    result_.refused = true;
    result_.share = 1.0;
    return result_;
  }
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
    // Float, stepping along x: the distances decide membership only (no safety bound rests on
    // the edge of the protective volume, which is a statistic's denominator).
    const Eigen::Isometry3d to_link = link.pose.inverse(Eigen::Isometry);
    const Eigen::Matrix3f rot = to_link.linear().cast<float>();
    const Eigen::Vector3f step_x = rot.col(0) * static_cast<float>(size);
    const auto reach_f = static_cast<float>(reach), padding_f = static_cast<float>(padding);
    for (std::int64_t z = a[2]; z <= b[2]; ++z) {
      for (std::int64_t y = a[1]; y <= b[1]; ++y) {
        const Eigen::Vector3d first =
            origin + (Eigen::Vector3d(a[0], y, z) + Eigen::Vector3d::Constant(0.5)) * size;
        Eigen::Vector3f local = (to_link * first).cast<float>();
        for (std::int64_t x = a[0]; x <= b[0]; ++x, local += step_x) {
          const float d = shapeDistanceT(link.shape, local);
          if (d > reach_f) continue;
          const std::int64_t cell = g.cellAt(x, y, z);
          auto& m = mark_[static_cast<std::size_t>(cell)];
          if (m == 0) marked_.push_back(cell);
          m |= d <= padding_f ? 3 : 1;
        }
      }
    }
  }
  for (const std::int64_t cell : marked_) {
    if (mark_[static_cast<std::size_t>(cell)] != 1) continue;  // inside the padded robot
    if (static_cast<double>(g.centre(cell).z()) < floor_z) continue;
    protective_.push_back(cell);
  }

  // 2. Sensor by sensor, the protective voxels no earlier sensor saw: in view, and nothing in
  //    front of them in the depth image, or else a walk that meets nothing.
  const std::size_t np = protective_.size();
  seen_.assign(np, 0);  // capacity kept: sized to every cell at configure()
  const int sensors_used = std::min(std::max(sensor_count, 0), max_sensors_);
  for (int s = 0; s < sensors_used; ++s) {
    const SensorSight& sight = sensors[s];
    if (sight.grid == nullptr || sight.grid->cells() != g.cells()) continue;
    const SensorFov& fov = sight.fov;
    // A view with a number that is not finite sees nothing (its voxels stay unseen).
    if (!fov.pose.matrix().allFinite() || !std::isfinite(fov.azimuth_min) ||
        !std::isfinite(fov.azimuth_max) || !std::isfinite(fov.elevation_min) ||
        !std::isfinite(fov.elevation_max) || !std::isfinite(fov.range_min) ||
        !std::isfinite(fov.range_max)) {
      continue;
    }
    const Eigen::Isometry3d to_sensor = fov.pose.inverse(Eigen::Isometry);
    fillDepth(sight, to_sensor);
    const Eigen::Matrix3f rot = to_sensor.linear().cast<float>();
    const Eigen::Vector3f shift = to_sensor.translation().cast<float>();
    for (std::size_t i = 0; i < np; ++i) {
      if (seen_[i] & 1) continue;
      const std::int64_t cell = protective_[i];
      const Bearing b = bearingOf(rot * g.centre(cell) + shift);
      if (!within(fov, b)) continue;
      const double range = b.range, az = b.azimuth, el = b.elevation;
      seen_[i] |= 2;  // in some view
      const std::uint8_t f = sight.grid->flags(cell);
      bool visible;
      if ((f & VoxelGrid::kHit) != 0) {
        visible = true;
      } else if ((f & VoxelGrid::kShadow) != 0) {
        visible = false;
      } else if (!all_near_ && static_cast<double>(depth_[static_cast<std::size_t>(binOf(az, el))]) >= range) {
        visible = true;  // nothing can be in front
      } else if (static_cast<double>(inner_[static_cast<std::size_t>(binOf(az, el))]) < range) {
        visible = false;  // certainly crossed a blocking voxel
      } else {
        // Every blocking voxel is entered at a range of at least the depth image's (its
        // sphere's nearest range, and the walk's entry into it is no nearer): the walk may stop
        // once the next voxel starts nearer the sensor than that.
        const std::size_t bin = static_cast<std::size_t>(binOf(az, el));
        const double until = all_near_ ? 1.0 : std::min(1.0, std::max(0.0, 1.0 - (static_cast<double>(depth_[bin]) - 1e-4) / range));
        ++result_.walks;
        visible = !blocked(*sight.grid, fov.pose.translation(), cell, until);
      }
      if (visible) seen_[i] |= 1;
    }
  }
  for (std::size_t i = 0; i < np; ++i) {
    if (seen_[i] & 1) continue;
    ++result_.unseen;
    ++((seen_[i] & 2) ? result_.shadowed : result_.outside_fov);
    unseen_cells_.push_back(protective_[i]);
  }
  result_.protective = static_cast<std::int64_t>(protective_.size());
  result_.share = result_.protective > 0
                      ? static_cast<double>(result_.unseen) / static_cast<double>(result_.protective)
                      : 0.0;
  return result_;
}

}  // namespace perception
}  // namespace workspace_proximity

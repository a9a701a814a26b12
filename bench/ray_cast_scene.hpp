#pragma once
/// A ray-cast robot cell for the perception benchmarks (perception_bench, cloud_latency_bench):
/// oriented boxes, the floor (z = 0) and a wall (x = wall_x), seen by a pinhole depth camera.

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Geometry>

namespace bench_scene {

struct Box {
  Eigen::Isometry3d pose;
  Eigen::Vector3d half;  ///< m, half extents
};

inline Box boxAt(const Eigen::Vector3d& c, const Eigen::Vector3d& half, double yaw, double pitch) {
  Box b;
  b.pose = Eigen::Translation3d(c) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY());
  b.half = half;
  return b;
}

/// Distance along the unit ray o + t d to the first box, the floor (z = 0) or the wall
/// (x = wall_x, facing +x); infinity when it hits nothing.
inline double castRay(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const std::vector<Box>& boxes,
                      double wall_x = -3.5) {
  double best = std::numeric_limits<double>::infinity();
  if (d.z() < 0.0) best = std::min(best, -o.z() / d.z());
  if (d.x() < 0.0) best = std::min(best, (wall_x - o.x()) / d.x());
  for (const Box& b : boxes) {
    const Eigen::Vector3d lo = b.pose.inverse() * o;
    const Eigen::Vector3d ld = b.pose.linear().transpose() * d;
    double t0 = 0.0, t1 = best;
    bool hit = true;
    for (int k = 0; k < 3 && hit; ++k) {
      if (std::abs(ld[k]) < 1e-12) {
        hit = std::abs(lo[k]) <= b.half[k];
        continue;
      }
      double u = (-b.half[k] - lo[k]) / ld[k], v = (b.half[k] - lo[k]) / ld[k];
      if (u > v) std::swap(u, v);
      t0 = std::max(t0, u);
      t1 = std::min(t1, v);
      hit = t0 <= t1;
    }
    if (hit) best = std::min(best, t0);
  }
  return best;
}

/// A Kinect-like depth camera (fx = fy = 525 px, principal point at the centre) at `eye`
/// looking at `target`.
struct DepthCamera {
  int width = 640;
  int height = 480;
  double fx = 525.0;
  double cx = 319.5;
  double cy = 239.5;
  double max_range = 6.0;   ///< m: farther returns are NaN
  double noise = 0.005;     ///< m, depth noise (1 sigma)
  double dropout = 0.02;    ///< share of pixels without a return (NaN)
  Eigen::Matrix3d rot;      ///< optical frame (x right, y down, z forward) in the fixed frame
  Eigen::Vector3d eye;

  DepthCamera(const Eigen::Vector3d& eye_at, const Eigen::Vector3d& target) : eye(eye_at) {
    const Eigen::Vector3d f = (target - eye).normalized();
    const Eigen::Vector3d right = f.cross(Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector3d down = f.cross(right);
    rot << right, down, f;
  }

  Eigen::Isometry3d pose() const {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = rot;
    p.translation() = eye;
    return p;
  }

  /// One frame: x, y, z (optical frame) at out[stride * pixel + 0..2], NaN where there is no return.
  void render(const std::vector<Box>& scene, std::mt19937& rng, float* out, int stride) const {
    std::normal_distribution<double> depth_noise(0.0, noise);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (int v = 0; v < height; ++v) {
      for (int u = 0; u < width; ++u) {
        const Eigen::Vector3d ray = Eigen::Vector3d((u - cx) / fx, (v - cy) / fx, 1.0).normalized();
        const double t = castRay(eye, rot * ray, scene);
        float* p = out + static_cast<std::ptrdiff_t>(stride) * (v * width + u);
        if (!(t < max_range) || uniform(rng) < dropout) {
          p[0] = p[1] = p[2] = nan;
          continue;
        }
        const double z = t * ray.z(), z_noisy = z + depth_noise(rng);
        const Eigen::Vector3d q = ray * t * (z_noisy / z);
        p[0] = static_cast<float>(q.x());
        p[1] = static_cast<float>(q.y());
        p[2] = static_cast<float>(q.z());
      }
    }
  }
};

}  // namespace bench_scene

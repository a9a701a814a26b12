// The octomap peer of bench/perception_bench.cpp: occupancy by insertion, the ROS default for
// camera-only cells (octomap_server, MoveIt's occupancy map), at the same 5 cm.

#include <chrono>
#include <cmath>

#include <octomap/OcTree.h>
#include <octomap/Pointcloud.h>

#include "perception_peers.hpp"

namespace perception_peers {

const char* const OctomapPeer::kStages[2] = {"points to octomap::Pointcloud", "insertPointCloud"};

struct OctomapPeer::Impl {
  Frame frame;
  Settings settings;
  bool crop = true;
  octomap::OcTree tree{0.05};
  octomap::Pointcloud points;
};

OctomapPeer::OctomapPeer(const Frame& frame, const Settings& settings, bool crop) : impl_(new Impl) {
  impl_->frame = frame;
  impl_->settings = settings;
  impl_->crop = crop;
  impl_->tree.setResolution(settings.voxel);
  impl_->points.reserve(static_cast<std::size_t>(frame.width) * frame.height);
}

OctomapPeer::~OctomapPeer() { delete impl_; }

Result OctomapPeer::run() {
  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
  Impl& m = *impl_;
  const Settings& s = m.settings;
  const float* T = m.frame.sensor_to_fixed;  // column-major
  Result r;
  const auto t0 = Clock::now();
  // As octomap_ros's pointCloud2ToOctomap does: finite points only, here already transformed.
  m.points.clear();
  const std::int64_t n = static_cast<std::int64_t>(m.frame.width) * m.frame.height;
  for (std::int64_t i = 0; i < n; ++i) {
    const float* p = m.frame.xyz + 3 * i;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    const float x = T[0] * p[0] + T[4] * p[1] + T[8] * p[2] + T[12];
    const float y = T[1] * p[0] + T[5] * p[1] + T[9] * p[2] + T[13];
    const float z = T[2] * p[0] + T[6] * p[1] + T[10] * p[2] + T[14];
    if (m.crop && (x < s.lower[0] || y < s.lower[1] || z < std::max(s.lower[2], s.floor_cut) ||
                   x > s.upper[0] || y > s.upper[1] || z > s.upper[2])) {
      continue;
    }
    m.points.push_back(x, y, z);
  }
  const auto t1 = Clock::now();
  const octomap::point3d origin(T[12], T[13], T[14]);
  m.tree.insertPointCloud(m.points, origin, s.max_range);
  const auto t2 = Clock::now();
  r.stage_ms[0] = ms(t1 - t0);
  r.stage_ms[1] = ms(t2 - t1);
  r.total_ms = ms(t2 - t0);
  r.points = static_cast<std::int64_t>(m.points.size());
  r.voxels = static_cast<std::int64_t>(m.tree.getNumLeafNodes());
  return r;
}

}  // namespace perception_peers

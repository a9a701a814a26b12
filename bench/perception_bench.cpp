// Perception benchmark (issue 23): the front end's per-frame rules on one core.
//   1. One 640 x 480 organised cloud (307 200 points), cloud in to clusters out
//      (CloudFrame::process: transform, NaNs, crop, floor, self-filter, voxels, clusters).
//   2. The unseen share of the protective volume for that frame (UnseenShare::compute).
//   3. A 1 000-beam floor scan, ranges in to clusters out (scanToPoints + CloudFrame::process).
// The scene is ray-cast here: a robot cell (floor, a wall behind the volume, an arm of four
// boxes, two people as boxes), seen by a depth camera (Kinect-like intrinsics, 5 mm depth
// noise, 2 % dropout as NaN, 6 m range) and a 270 degree floor scanner. Median, p90 and p99
// over many frames; writes a markdown table to stdout (and --out FILE). Timings, not tests.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <thread>
#include <string>
#include <vector>

#include "workspace_proximity/perception/cloud_frame.hpp"
#include "workspace_proximity/perception/laser_scan.hpp"
#include "workspace_proximity/perception/unseen_share.hpp"

namespace wp = workspace_proximity;
namespace pc = workspace_proximity::perception;

namespace {

struct Box {
  Eigen::Isometry3d pose;
  Eigen::Vector3d half;
};

// Distance along the unit ray o + t d to the first box, floor (z = 0) or wall (x = -3.5).
double castRay(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const std::vector<Box>& boxes) {
  double best = std::numeric_limits<double>::infinity();
  if (d.z() < 0.0) best = std::min(best, -o.z() / d.z());
  if (d.x() < 0.0) best = std::min(best, (-3.5 - o.x()) / d.x());
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

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5))];
}

std::string machine() {
  std::ifstream cpu("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  while (std::getline(cpu, line)) {
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  }
  std::ifstream load("/proc/loadavg");
  std::string l1;
  load >> l1;
  std::ostringstream s;
  s << model << ", " << std::thread::hardware_concurrency() << " cores, load average " << l1
    << " at the start";
  return s.str();
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_path;
  int frames = 300;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) out_path = argv[++i];
    if (a == "--quick") frames = 60;
  }
  const std::string where = machine();

  // The cell: an arm of four boxes at the origin, two people.
  auto boxAt = [](const Eigen::Vector3d& c, const Eigen::Vector3d& half, double yaw, double pitch) {
    Box b;
    b.pose = Eigen::Translation3d(c) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
             Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY());
    b.half = half;
    return b;
  };
  std::vector<Box> arm = {boxAt({0, 0, 0.3}, {0.1, 0.1, 0.3}, 0, 0),
                          boxAt({0.25, 0, 0.7}, {0.3, 0.06, 0.06}, 0, -0.3),
                          boxAt({0.6, 0.1, 0.8}, {0.25, 0.05, 0.05}, 0.5, 0),
                          boxAt({0.8, 0.25, 0.7}, {0.05, 0.05, 0.08}, 0, 0)};
  std::vector<Box> scene = arm;
  scene.push_back(boxAt({1.2, -0.8, 0.9}, {0.25, 0.2, 0.9}, 0, 0));
  scene.push_back(boxAt({-1.0, 1.2, 0.9}, {0.25, 0.2, 0.9}, 0.4, 0));
  std::vector<pc::SelfLink> links;
  for (const Box& b : arm) {
    pc::SelfLink l;
    l.shape = wp::Shape::box(b.half);
    l.pose = b.pose;
    l.speed = 1.0;  // m/s
    links.push_back(l);
  }

  // The depth camera: 640 x 480, fx = fy = 525 px, looking from (2.8, 1.2, 2.0) at the arm.
  const Eigen::Vector3d eye(2.8, 1.2, 2.0), target(0, 0, 0.7);
  const Eigen::Vector3d f = (target - eye).normalized();
  const Eigen::Vector3d right = f.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = f.cross(right);
  Eigen::Matrix3d rot;
  rot << right, down, f;  // optical frame: x right, y down, z forward
  const int width = 640, height = 480;
  const double fx = 525.0, cx = 319.5, cy = 239.5;
  std::vector<float> cloud(static_cast<std::size_t>(3 * width * height));
  std::mt19937 rng(42);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const Eigen::Vector3d ray = Eigen::Vector3d((u - cx) / fx, (v - cy) / fx, 1.0).normalized();
      const double t = castRay(eye, rot * ray, scene);
      float* p = cloud.data() + 3 * (v * width + u);
      if (!(t < 6.0) || uniform(rng) < 0.02) {
        p[0] = p[1] = p[2] = nan;
        continue;
      }
      const double z = t * ray.z(), z_noisy = z + noise(rng);
      const Eigen::Vector3d q = ray * t * (z_noisy / z);
      p[0] = static_cast<float>(q.x());
      p[1] = static_cast<float>(q.y());
      p[2] = static_cast<float>(q.z());
    }
  }
  Eigen::Isometry3d cam = Eigen::Isometry3d::Identity();
  cam.linear() = rot;
  cam.translation() = eye;
  pc::CloudView view = pc::packedXyz(cloud.data(), static_cast<std::int64_t>(width) * height);
  view.width = width;
  view.height = height;
  view.row_step = 12 * width;

  pc::CloudFrameParams params;
  const double reach = pc::robotReach(links.data(), static_cast<int>(links.size()), Eigen::Vector3d::Zero());
  const double ssm_reach = 1.5;
  params.volume = pc::defaultMonitoredVolume(Eigen::Vector3d::Zero(), reach, ssm_reach, 0.0);
  pc::CloudFrame frame(params);

  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
  std::vector<double> cloud_ms, unseen_ms, scan_ms;
  pc::UnseenShare unseen(4);
  unseen.configure(frame.grid());
  pc::SensorSight sight;
  // The field of view in the camera's body frame (x forward, y left, z up).
  Eigen::Matrix3d optical_body;
  optical_body << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  sight.fov.pose = cam;
  sight.fov.pose.linear() = rot * optical_body;
  sight.fov.azimuth_min = -std::atan(cx / fx);
  sight.fov.azimuth_max = std::atan(cx / fx);
  sight.fov.elevation_min = -std::atan(cy / fx);
  sight.fov.elevation_max = std::atan(cy / fx);
  sight.fov.range_max = 6.0;
  sight.grid = &frame.grid();
  const Eigen::Isometry3f cam_f = cam.cast<float>();
  for (int i = 0; i < frames + 10; ++i) {
    const auto t0 = Clock::now();
    frame.setRobot(links.data(), static_cast<int>(links.size()), 0.01);
    frame.process(view, cam_f);
    const auto t1 = Clock::now();
    unseen.compute(links.data(), static_cast<int>(links.size()), ssm_reach, params.self_padding,
                   params.floor_height + params.floor_tolerance, &sight, 1);
    const auto t2 = Clock::now();
    if (i >= 10) {  // warm-up frames left out
      cloud_ms.push_back(ms(t1 - t0));
      unseen_ms.push_back(ms(t2 - t1));
    }
  }
  const pc::CloudFrameStats cs = frame.stats();
  const pc::UnseenResult us = unseen.result();

  // The floor scanner: 1 000 beams over 270 degrees, 0.15 m above the floor at (0, -2.3),
  // facing +y; each beam extruded from 0.15 m below the scan plane to 0.85 m above.
  const Eigen::Vector3d scanner(0.0, -2.3, 0.15);
  const int beams = 1000;
  const double angle_min = -0.75 * M_PI, increment = 1.5 * M_PI / (beams - 1);
  std::vector<float> ranges(beams);
  for (int b = 0; b < beams; ++b) {
    const double a = M_PI / 2 + angle_min + b * increment;
    const double t = castRay(scanner, Eigen::Vector3d(std::cos(a), std::sin(a), 0.0), scene);
    ranges[static_cast<std::size_t>(b)] = t < 10.0 ? static_cast<float>(t + noise(rng)) : std::numeric_limits<float>::infinity();
  }
  pc::ScanView scan;
  scan.ranges = ranges.data();
  scan.count = beams;
  scan.angle_min = static_cast<float>(angle_min);
  scan.angle_increment = static_cast<float>(increment);
  scan.range_min = 0.05f;
  scan.range_max = 10.0f;
  const pc::ScanBand band{-0.15f, 0.85f, 0.025f};
  const Eigen::Isometry3f scan_pose(Eigen::Translation3f(scanner.cast<float>()) *
                                    Eigen::AngleAxisf(static_cast<float>(M_PI / 2), Eigen::Vector3f::UnitZ()));
  pc::ScanResult sr;
  for (int i = 0; i < frames * 10 + 10; ++i) {
    const auto t0 = Clock::now();
    frame.setRobot(links.data(), static_cast<int>(links.size()), 0.01);
    frame.processScan(scan, band, scan_pose);
    sr = frame.scanResult();
    const auto t1 = Clock::now();
    if (i >= 10) scan_ms.push_back(ms(t1 - t0));
  }
  const pc::CloudFrameStats ss = frame.stats();

  std::ostringstream o;
  o << "# Perception front end (bench/perception_bench.cpp)\n\n"
    << "Machine: " << where << ". One thread; Release; " << frames << " cloud frames, "
    << frames * 10 << " scans (after 10 warm-up frames each).\n\n"
    << "Volume " << frame.grid().nx() << " x " << frame.grid().ny() << " x " << frame.grid().nz()
    << " voxels of " << params.voxel_size * 100 << " cm (robot reach " << reach << " m + R "
    << ssm_reach << " m).\n\n"
    << "| stage | input | median ms | p90 ms | p99 ms | target |\n|---|---|---:|---:|---:|---|\n";
  char line[256];
  std::snprintf(line, sizeof line, "| cloud in -> clusters out | 640 x 480 organised (307 200 points) | %.2f | %.2f | %.2f | <= 5 ms median |\n",
                percentile(cloud_ms, 0.5), percentile(cloud_ms, 0.9), percentile(cloud_ms, 0.99));
  o << line;
  std::snprintf(line, sizeof line, "| unseen share of the protective volume | %lld voxels within R, 1 camera | %.2f | %.2f | %.2f | - |\n",
                static_cast<long long>(us.protective), percentile(unseen_ms, 0.5), percentile(unseen_ms, 0.9), percentile(unseen_ms, 0.99));
  o << line;
  std::snprintf(line, sizeof line, "| scan in -> clusters out | 1 000 beams x %d layers | %.3f | %.3f | %.3f | <= 0.5 ms median |\n",
                band.layers(), percentile(scan_ms, 0.5), percentile(scan_ms, 0.9), percentile(scan_ms, 0.99));
  o << line << "\n";
  o << "Cloud frame: " << cs.points_in << " points, " << cs.non_finite << " NaN, " << cs.outside_volume
    << " outside the volume, " << cs.floor << " floor, " << cs.self << " robot, " << cs.near_robot
    << " within 5 cm of the padded robot, " << cs.kept << " kept; " << cs.voxels << " occupied voxels, "
    << cs.clusters << " clusters (" << cs.clusters_small << " below min points).\n"
    << "Unseen: " << us.unseen << " of " << us.protective << " protective voxels (share "
    << us.share << "; " << us.outside_fov << " outside the view, " << us.shadowed << " shadowed; "
    << us.walks << " lines of sight walked).\n"
    << "Scan: " << sr.beams << " valid beams, " << sr.points << " points, " << ss.clusters
    << " clusters.\n";
  std::fputs(o.str().c_str(), stdout);
  if (!out_path.empty()) std::ofstream(out_path) << o.str();
  return 0;
}

// Perception benchmark (issue 23): the front end's per-frame rules on one core.
//   1. One 640 x 480 organised cloud (307 200 points), cloud in to tracked boxes out
//      (CloudFrame::process: transform, NaNs, crop, floor, self-filter, voxels, clusters; then
//      ClusterTracks::update, as cloud_tracker does before it publishes perceived_objects).
//   2. The unseen share of the protective volume for that frame (UnseenShare::compute).
//   3. A 1 000-beam floor scan, ranges in to tracked boxes out (processScan + ClusterTracks).
//   4. The peers on the same frame, in the same rounds as 1 (alternating, order rotated each
//      round): PCL's VoxelGrid + EuclideanClusterExtraction when built with
//      -DWP_BENCH_PERCEPTION_PEERS=ON, octomap's OcTree::insertPointCloud when liboctomap-dev is
//      there (perception_peers.hpp); medians, means, p99s and the ratios to ours.
// Options: --quick (60 rounds), --frames N (300), --octomap-every K (octomap in every K-th round,
// 5), --out FILE.
// The scene is ray-cast here: a robot cell (floor, a wall behind the volume, an arm of four
// boxes, two people as boxes), seen by a depth camera (Kinect-like intrinsics, 5 mm depth
// noise, 2 % dropout as NaN, 6 m range) and a 270 degree floor scanner. Median, p90 and p99
// over many frames; writes a markdown table to stdout (and --out FILE). Timings, not tests.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <thread>
#include <string>
#include <vector>

#include "workspace_proximity/perception/cloud_frame.hpp"
#include "workspace_proximity/perception/cluster_tracks.hpp"
#include "workspace_proximity/perception/laser_scan.hpp"
#include "workspace_proximity/perception/unseen_share.hpp"
#include "perception_peers.hpp"
#include "ray_cast_scene.hpp"

namespace wp = workspace_proximity;
namespace pc = workspace_proximity::perception;
namespace peers = perception_peers;

namespace {

using bench_scene::Box;
using bench_scene::boxAt;
using bench_scene::castRay;

enum class Kind { kOurs, kPcl, kOctomapCropped, kOctomapWhole };

// One row of the cloud comparison: its per-frame totals and stage times (ms).
struct Contestant {
  Kind kind;
  std::string name;
  std::string what;
  int every;  // runs in every every-th round
  std::vector<double> total_ms;
  std::array<std::vector<double>, 4> stage_ms;
  peers::Result last;
};

double mean(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
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
  char when[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(when, sizeof when, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  s << model << ", " << std::thread::hardware_concurrency() << " cores; " << when << "; load average " << l1
    << " at the start";
  return s.str();
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_path;
  int frames = 300;
  int octomap_every = 5;  // octomap's insertion is tens of times dearer: every fifth round
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) out_path = argv[++i];
    if (a == "--quick") frames = 60;
    if (a == "--frames" && i + 1 < argc) frames = std::max(1, std::atoi(argv[++i]));
    if (a == "--octomap-every" && i + 1 < argc) octomap_every = std::max(1, std::atoi(argv[++i]));
  }
  const std::string where = machine();

  // The cell: an arm of four boxes at the origin, two people.
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

  // The peers get the same frame, the same volume (above the same floor cut), voxel size and
  // the cluster tolerance that joins what ours joins: ours links voxels through faces, edges
  // and corners, whose centres are at most sqrt(3) voxels apart (PCL's voxels are centroids
  // of their points, so its clusters can differ a little at the edges; both counts are shown).
  peers::Frame peer_frame;
  peer_frame.xyz = cloud.data();
  peer_frame.width = width;
  peer_frame.height = height;
  Eigen::Map<Eigen::Matrix4f>(peer_frame.sensor_to_fixed) = cam_f.matrix();
  peers::Settings peer_settings;
  {
    // The grid's volume: ours rounds the configured box out to whole voxels.
    const wp::Aabb box = frame.grid().box();
    for (int k = 0; k < 3; ++k) {
      peer_settings.lower[k] = static_cast<float>(box.lower[k]);
      peer_settings.upper[k] = static_cast<float>(box.upper[k]);
    }
  }
  peer_settings.floor_cut = static_cast<float>(params.floor_height + params.floor_tolerance);
  peer_settings.voxel = static_cast<float>(params.voxel_size);
  peer_settings.cluster_tolerance = static_cast<float>(std::sqrt(3.0) * params.voxel_size);
  peer_settings.min_cluster_size = 1;
  peer_settings.max_range = 6.0f;
  std::vector<Contestant> contestants;
  contestants.push_back({Kind::kOurs, "ours: CloudFrame::process + ClusterTracks::update", "transform, NaNs, crop, floor, self-filter, voxels, clusters, tracks", 1, {}, {}, {}});
#ifdef WP_BENCH_PCL
  peers::PclPeer pcl_peer(peer_frame, peer_settings);
  contestants.push_back({Kind::kPcl, "PCL 1.13: VoxelGrid + EuclideanClusterExtraction",
                         "transformPointCloud, CropBox, VoxelGrid, KdTree + EuclideanClusterExtraction (tolerance sqrt(3) voxels); no self-filter (the arm stays, a cluster of its own)",
                         1, {}, {}, {}});
#endif
#ifdef WP_BENCH_OCTOMAP
  peers::OctomapPeer octo_cropped(peer_frame, peer_settings, true);
  peers::OctomapPeer octo_whole(peer_frame, peer_settings, false);
  contestants.push_back({Kind::kOctomapCropped, "octomap 1.9: OcTree::insertPointCloud, cropped", "the cropped points (as ours keeps them), rays from the sensor, 5 cm, max range 6 m, one persistent tree", octomap_every, {}, {}, {}});
  contestants.push_back({Kind::kOctomapWhole, "octomap 1.9: OcTree::insertPointCloud, whole frame", "every finite point of the frame, rays from the sensor, 5 cm, max range 6 m, one persistent tree", octomap_every, {}, {}, {}});
#endif
  const int n_contestants = static_cast<int>(contestants.size());
  // Ours goes on to boxes with ids and velocities, as cloud_tracker publishes them: the
  // clusters into the tracker (pc::ClusterTracks, its defaults).
  pc::ClusterTracks cloud_tracks{pc::ClusterTrackParams()};
  // One round runs every contestant once (the octomap rows every octomap_every-th round), in
  // an order rotated by one each round, so that whatever the machine does meanwhile falls on
  // all of them alike.
  for (int i = 0; i < frames + 10; ++i) {
    for (int j = 0; j < n_contestants; ++j) {
      const int c = (i + j) % n_contestants;
      Contestant& who = contestants[static_cast<std::size_t>(c)];
      if (i % who.every != 0) continue;
      peers::Result r;
      if (who.kind == Kind::kOurs) {
        const auto t0 = Clock::now();
        frame.setRobot(links.data(), static_cast<int>(links.size()), 0.01);
        frame.process(view, cam_f);
        cloud_tracks.update(static_cast<wp::Stamp>(i) * 33333333, frame.detections());  // 30 Hz
        const auto t1 = Clock::now();
        unseen.compute(links.data(), static_cast<int>(links.size()), ssm_reach, params.self_padding,
                       params.floor_height + params.floor_tolerance, &sight, 1);
        const auto t2 = Clock::now();
        r.total_ms = ms(t1 - t0);
        r.points = frame.stats().kept + frame.stats().near_robot;
        r.voxels = frame.stats().voxels;
        r.clusters = frame.stats().clusters;
        if (i >= 10) unseen_ms.push_back(ms(t2 - t1));
      }
#ifdef WP_BENCH_PCL
      else if (who.kind == Kind::kPcl) {
        r = pcl_peer.run();
      }
#endif
#ifdef WP_BENCH_OCTOMAP
      else if (who.kind == Kind::kOctomapCropped) {
        r = octo_cropped.run();
      } else if (who.kind == Kind::kOctomapWhole) {
        r = octo_whole.run();
      }
#endif
      if (i < 10) continue;  // warm-up rounds left out
      who.total_ms.push_back(r.total_ms);
      for (int k = 0; k < 4; ++k) who.stage_ms[static_cast<std::size_t>(k)].push_back(r.stage_ms[k]);
      who.last = r;
    }
  }
  cloud_ms = contestants[0].total_ms;
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
  pc::ClusterTracks scan_tracks{pc::ClusterTrackParams()};
  for (int i = 0; i < frames * 10 + 10; ++i) {
    const auto t0 = Clock::now();
    frame.setRobot(links.data(), static_cast<int>(links.size()), 0.01);
    frame.processScan(scan, band, scan_pose);
    scan_tracks.update(static_cast<wp::Stamp>(i) * 25000000, frame.detections());  // 40 Hz
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
  char line[512];
  std::snprintf(line, sizeof line, "| cloud in -> tracked boxes out | 640 x 480 organised (307 200 points) | %.2f | %.2f | %.2f | <= 5 ms median |\n",
                percentile(cloud_ms, 0.5), percentile(cloud_ms, 0.9), percentile(cloud_ms, 0.99));
  o << line;
  std::snprintf(line, sizeof line, "| unseen share of the protective volume | %lld voxels within R, 1 camera | %.2f | %.2f | %.2f | - |\n",
                static_cast<long long>(us.protective), percentile(unseen_ms, 0.5), percentile(unseen_ms, 0.9), percentile(unseen_ms, 0.99));
  o << line;
  std::snprintf(line, sizeof line, "| scan in -> tracked boxes out | 1 000 beams x %d layers | %.3f | %.3f | %.3f | <= 0.5 ms median |\n",
                band.layers(), percentile(scan_ms, 0.5), percentile(scan_ms, 0.9), percentile(scan_ms, 0.99));
  o << line << "\n";
  // The peers on the same frame, in the same rounds: ratio = the row's median (mean, p99) /
  // ours. Ours here is the cloud row above (the same samples).
  o << "## The same frame through the peers (alternating, same process)\n\n"
    << "Each round runs every row once, in an order rotated by one each round; the octomap rows run "
    << "in every " << octomap_every << "th round. ratio = the row's figure / ours (above 1 ours is faster).\n\n"
    << "| row | what it does | frames | median ms | mean ms | p99 ms | ratio median | ratio mean | ratio p99 | points in | voxels | clusters | stages, median ms |\n"
    << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  const Contestant& ours = contestants[0];
  const double ours_med = percentile(ours.total_ms, 0.5), ours_mean = mean(ours.total_ms),
               ours_p99 = percentile(ours.total_ms, 0.99);
  for (int c = 0; c < n_contestants; ++c) {
    const Contestant& who = contestants[static_cast<std::size_t>(c)];
    const double med = percentile(who.total_ms, 0.5), avg = mean(who.total_ms), p99 = percentile(who.total_ms, 0.99);
    std::string stages = "-";
#ifdef WP_BENCH_PCL
    if (who.kind == Kind::kPcl) {
      stages.clear();
      for (int k = 0; k < 4; ++k) {
        std::snprintf(line, sizeof line, "%s%s %.2f", k ? "; " : "", peers::PclPeer::kStages[k],
                      percentile(who.stage_ms[static_cast<std::size_t>(k)], 0.5));
        stages += line;
      }
    }
#endif
#ifdef WP_BENCH_OCTOMAP
    if (who.kind == Kind::kOctomapCropped || who.kind == Kind::kOctomapWhole) {
      stages.clear();
      for (int k = 0; k < 2; ++k) {
        std::snprintf(line, sizeof line, "%s%s %.2f", k ? "; " : "", peers::OctomapPeer::kStages[k],
                      percentile(who.stage_ms[static_cast<std::size_t>(k)], 0.5));
        stages += line;
      }
    }
#endif
    std::snprintf(line, sizeof line, "| %s | ", who.name.c_str());
    o << line << who.what;
    std::snprintf(line, sizeof line, " | %zu | %.2f | %.2f | %.2f | %.1f | %.1f | %.1f | %lld | %lld | %d | ",
                  who.total_ms.size(), med, avg, p99, med / ours_med, avg / ours_mean, p99 / ours_p99,
                  static_cast<long long>(who.last.points), static_cast<long long>(who.last.voxels), who.last.clusters);
    o << line << stages << " |\n";
  }
  if (n_contestants == 1) {
    o << "\n(No peer built: configure with -DWP_BENCH_PERCEPTION_PEERS=ON, scripts/bench-perception --peers.)\n";
  }
  o << "\nPoints in: the points each row clusters or inserts (ours: kept after crop, floor and self-filter); voxels: "
       "ours occupied voxels, PCL voxel centroids, octomap leaves in its tree (free and occupied, the whole map). "
       "octomap makes occupancy, not clusters.\n\n";
  o << "Cloud frame: " << cs.points_in << " points, " << cs.non_finite << " NaN, " << cs.outside_volume
    << " outside the volume, " << cs.floor << " floor, " << cs.self << " robot, " << cs.near_robot
    << " within 5 cm of the padded robot, " << cs.kept << " kept; " << cs.voxels << " occupied voxels, "
    << cs.clusters << " clusters (" << cs.clusters_small << " below min points).\n"
    << "Unseen: " << us.unseen << " of " << us.protective << " protective voxels (share "
    << us.share << "; " << us.outside_fov << " outside the view, " << us.shadowed << " shadowed; "
    << us.walks << " lines of sight walked).\n"
    << "Scan: " << sr.beams << " valid beams, " << sr.points << " points, " << ss.clusters
    << " clusters; tracks: " << cloud_tracks.tracks().size() << " from the cloud, " << scan_tracks.tracks().size()
    << " from the scan.\n";
  std::fputs(o.str().c_str(), stdout);
  if (!out_path.empty()) std::ofstream(out_path) << o.str();
  return 0;
}
